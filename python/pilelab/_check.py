"""The checks every reader applies, as the C++ readers do: a damaged file is refused on reading
with its path, the field (HDF5 object or JSON key) and what was expected, not returned as
arrays that fail later, far from their cause."""
import numpy as np


class FormatError(ValueError):
    """A file that is not what pilelab writes: missing, damaged, truncated, of another version,
    or with a field of the wrong shape, type or value. The message starts with the file's path,
    then names the field and what was expected."""


class MissingFileError(FormatError, FileNotFoundError):
    """A run directory, or a file a helper needs, that is not there. Also a FileNotFoundError,
    which load() raised for these before FormatError existed."""


def fail(path, field, what):
    raise FormatError(f"{path}: {field}: {what}")


def shape_text(shape):
    inner = ", ".join(str(d) for d in shape)
    return f"({inner},)" if len(shape) == 1 else f"({inner})"


def require_shape(path, field, array, shape):
    """array's shape must be `shape`, whose entries are ints (fixed) or names such as "n" (any
    length); returns array."""
    ok = array.ndim == len(shape) and all(isinstance(want, str) or got == want
                                          for got, want in zip(array.shape, shape))
    if not ok:
        fail(path, field, f"shape {shape_text(array.shape)}, expected {shape_text(shape)}")
    return array


def require_numbers(path, field, array):
    if array.dtype.kind not in "iuf":
        fail(path, field, f"holds {array.dtype}; expected numbers")
    return array


def require_integers(path, field, array):
    if array.dtype.kind not in "iu":
        fail(path, field, f"holds {array.dtype}; expected integers (indices or counts)")
    return array


def row_text(array, flat_index):
    """'row i' or 'row i, column j' of an element of array, by its index into array.ravel()."""
    if array.ndim < 2:
        return f"row {flat_index}"
    row, column = np.unravel_index(flat_index, array.shape)[:2]
    return f"row {row}, column {column}"


def first(mask):
    """The flat index of the first True of mask, or None."""
    hits = np.flatnonzero(mask)
    return int(hits[0]) if hits.size else None


def require_finite(path, field, array):
    """Every value a number: NaN or infinity is damage (the C++ readers refuse it too)."""
    bad = first(~np.isfinite(array))
    if bad is not None:
        value = array.ravel()[bad]
        fail(path, field, f"{row_text(array, bad)} is {'NaN' if np.isnan(value) else 'infinite'}; expected finite numbers")
    return array


def require_index_range(path, field, array, low, high, meaning):
    """Every value in [low, high): indices into another array (meaning says which)."""
    bad = first((array < low) | (array >= high))
    if bad is not None:
        fail(path, field, f"{row_text(array, bad)} is {array.ravel()[bad]}; expected {low} .. {high - 1} ({meaning})")
    return array
