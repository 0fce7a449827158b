"""Small helpers over h5py: strings as str, units from the `unit` attribute, and every read
checked, so that a missing, damaged or misshapen object is a FormatError naming the file and
the object (h5py's own errors name neither the file nor, often, the object)."""
import math

import h5py
import numpy as np

from pilelab._check import fail, require_finite, require_integers, require_numbers, require_shape
from pilelab._probe import probe

# The layout version this package reads (docs/FORMAT.md); a later one is refused, not misread.
FORMAT_VERSION = 1


def text(value):
    """An HDF5 string (bytes, numpy bytes, a 0-d array or str) as str."""
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value[()]
    if isinstance(value, (bytes, np.bytes_)):
        return bytes(value).decode("utf-8")
    return str(value)


def attribute(obj, name, default=None):
    """An attribute with strings decoded; default when absent."""
    try:
        if name not in obj.attrs:
            return default
        value = obj.attrs[name]
    except (OSError, RuntimeError, KeyError) as e:  # a damaged object header
        fail(path_of(obj), obj.name, f"cannot read attribute {name} ({e}): a damaged file")
    if isinstance(value, (bytes, np.bytes_, str)):
        return text(value)
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value[()]
    if isinstance(value, np.generic):
        return value.item()
    return value


def path_of(obj):
    return obj.file.filename


def required_attribute(obj, name, kind):
    """Attribute name of obj, which must be present and of kind str, int or float (an int is a
    float too)."""
    value = attribute(obj, name)
    if value is None:
        fail(path_of(obj), obj.name, f"missing attribute {name}")
    accepted = (int, float) if kind is float else (kind,)
    if not isinstance(value, accepted) or isinstance(value, bool):
        expected = {str: "a string", int: "an integer", float: "a number"}[kind]
        fail(path_of(obj), obj.name, f"attribute {name} is {value!r}; expected {expected}")
    if kind is float and not math.isfinite(value):
        fail(path_of(obj), obj.name, f"attribute {name} is {value!r}; expected a finite number")
    return value


def child(group, name, kind):
    """group[name], which must be an h5py.Group or h5py.Dataset (kind)."""
    full = f"{group.name.rstrip('/')}/{name}"
    what = "group" if kind is h5py.Group else "dataset"
    try:
        obj = group.get(name)
    except (OSError, RuntimeError, KeyError) as e:  # a damaged link table or object header
        fail(path_of(group), full, f"cannot read the {what} ({e}): a damaged file")
    if obj is None:
        fail(path_of(group), full, f"missing {what}")
    if not isinstance(obj, kind):
        fail(path_of(group), full, f"expected a {what}, found a {'group' if isinstance(obj, h5py.Group) else 'dataset'}")
    return obj


def read(group, name, units, shape=None, integers=False, finite=False):
    """group's dataset name as a numpy array, its unit recorded in units[name] ("" when it has
    none). Checked: numbers (integers if asked), of the given shape (see require_shape), and
    finite if asked."""
    dataset = child(group, name, h5py.Dataset)
    path, field = path_of(group), dataset.name
    try:
        array = np.asarray(dataset[()])
    except (OSError, RuntimeError, TypeError) as e:
        fail(path, field, f"cannot read the dataset ({e}): a damaged file")
    (require_integers if integers else require_numbers)(path, field, array)
    if shape is not None:
        require_shape(path, field, array, shape)
    if finite:
        require_finite(path, field, array)
    units[name.split("/")[-1]] = attribute(dataset, "unit", "")
    return array


def open_file(path, expected_format):
    """Opens path read-only and checks the root attributes `format` and `format_version`. A
    child process reads the whole file first (pilelab._probe), so that a file damaged in a way
    that crashes libhdf5 is refused rather than crashing this process."""
    probe(path)
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        fail(path, "/", f"cannot open as HDF5 ({e}): not an HDF5 file, or a truncated or damaged one")
    try:
        found = attribute(f, "format")
        if found != expected_format:
            fail(path, "/", f"root attribute format is {found!r}; expected {expected_format!r}")
        version = attribute(f, "format_version")
        if version is None:
            fail(path, "/", f"root attribute format_version missing; expected {FORMAT_VERSION}")
        if not isinstance(version, int) or isinstance(version, bool) or version != FORMAT_VERSION:
            fail(path, "/", f"root attribute format_version = {version!r}; this reader reads version {FORMAT_VERSION} "
                            "(docs/FORMAT.md)")
    except BaseException:
        f.close()
        raise
    return f
