"""Small helpers over h5py: strings as str, units from the `unit` attribute."""
import h5py
import numpy as np


def text(value):
    """An HDF5 string (bytes, numpy bytes, a 0-d array or str) as str."""
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value[()]
    if isinstance(value, (bytes, np.bytes_)):
        return bytes(value).decode("utf-8")
    return str(value)


def attribute(obj, name, default=None):
    """An attribute with strings decoded; default when absent."""
    if name not in obj.attrs:
        return default
    value = obj.attrs[name]
    if isinstance(value, (bytes, np.bytes_, str)):
        return text(value)
    if isinstance(value, np.ndarray) and value.shape == () :
        value = value[()]
    if isinstance(value, np.generic):
        return value.item()
    return value


def read(group, name, units):
    """The dataset as a numpy array, its unit recorded in units[name] ("" when it has none)."""
    dataset = group[name]
    units[name.split("/")[-1]] = attribute(dataset, "unit", "")
    return dataset[()]


def open_file(path, expected_format):
    """Opens path read-only and checks the root attribute `format`."""
    f = h5py.File(path, "r")
    found = attribute(f, "format")
    if found != expected_format:
        f.close()
        raise ValueError(f"{path}: root attribute format is {found!r}; expected {expected_format!r}")
    return f
