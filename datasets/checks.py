"""Argument checks shared by the generators, the scene registry, the file loaders and the viewers.

Each check names the argument it was given and says what is wrong, as a ValueError (a TypeError
would name only Python's view of the problem); each returns the value in the form callers use.
"""

from __future__ import annotations

import numbers
import os
import stat

import numpy as np

from conecull._api import memory_bytes  # noqa: F401 (re-exported: the loaders' and the bench's bound)


def is_int(value) -> bool:
    """A Python or NumPy integer, and not a bool."""
    return not isinstance(value, (bool, np.bool_)) and isinstance(value, (int, np.integer))


def count(name: str, value, low: int, high: int | None = None) -> int:
    """An integer in [low, high] (bool is not a count); no silent clamping."""
    if is_int(value) and value >= low and (high is None or value <= high):
        return int(value)
    want = f"an integer >= {low}" if high is None else f"an integer in [{low}, {high}]"
    raise ValueError(f"{name}: expected {want}, got {value!r}")


def real(name: str, value, low: float | None = None, high: float | None = None, *, low_open: bool = False,
         high_open: bool = False) -> float:
    """A finite real number within the bounds given (open or closed); NaN and inf never pass."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "fiu":
        value = value.item()  # a 0-d array is a number
    ok = not isinstance(value, (bool, np.bool_)) and isinstance(value, numbers.Real) and np.isfinite(value)
    if ok:
        v = float(value)
        ok = ((low is None or (v > low if low_open else v >= low)) and
              (high is None or (v < high if high_open else v <= high)))
        if ok:
            return v
    bounds = []
    if low is not None:
        bounds.append(f"{'>' if low_open else '>='} {low:g}")
    if high is not None:
        bounds.append(f"{'<' if high_open else '<='} {high:g}")
    raise ValueError(f"{name}: expected a finite number{' ' + ' and '.join(bounds) if bounds else ''}, got {value!r}")


def seed(name: str, value):
    """A random seed as np.random.default_rng takes it: a non-negative integer, None (fresh
    entropy) or a SeedSequence."""
    if value is None or isinstance(value, np.random.SeedSequence):
        return value
    return count(name, value, 0)


def fits_in_memory(name: str, n_bytes: float, what: str) -> None:
    """Refuse, before allocating, a size this machine cannot hold: NumPy would raise its own
    MemoryError at best, and at worst the machine swaps or a Python loop runs for hours."""
    mem = memory_bytes()
    if n_bytes > mem:
        raise ValueError(f"{name}: {what} would need about {n_bytes / 2**30:.3g} GiB, more than this machine's "
                         f"{mem / 2**30:.3g} GiB of memory")


def regular_file(name: str, path: str) -> None:
    """Before reading a file: a regular one. A FIFO blocks the reader until something writes to
    it, and a device such as /dev/zero never ends (a bad-input probe hung on both)."""
    try:
        mode = os.stat(path).st_mode
    except OSError as e:
        raise ValueError(f"{name}: cannot read '{path}' ({e.strerror or e})") from None
    if not stat.S_ISREG(mode):
        kind = "a FIFO" if stat.S_ISFIFO(mode) else "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else \
            "a socket" if stat.S_ISSOCK(mode) else "a folder" if stat.S_ISDIR(mode) else "not a regular file"
        raise ValueError(f"{name}: '{path}' is {kind}, not a regular file")


def writable_file(name: str, path, example: str = "run.rrd") -> str:
    """A file path that can be written: checked before the work whose result goes there."""
    if not isinstance(path, (str, os.PathLike)) or not os.fspath(path):
        raise ValueError(f"{name}: expected a file path, got {path!r}")
    path = os.fspath(path)
    if os.path.isdir(path):
        raise ValueError(f"{name}: '{path}' is a directory; give a file name such as {os.path.join(path, example)}")
    parent = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(parent):
        raise ValueError(f"{name}: folder '{parent}' does not exist")
    existed = os.path.exists(path)
    if existed and (stat.S_ISFIFO(mode := os.stat(path).st_mode) or stat.S_ISSOCK(mode)):
        raise ValueError(f"{name}: '{path}' is a FIFO or a socket, not a file (opening it would wait for a reader)")
    try:  # really open it: permissions, read-only or special file systems (/proc) all show here
        with open(path, "ab"):
            pass
    except OSError as e:
        raise ValueError(f"{name}: cannot write '{path}' ({e.strerror or e})") from None
    if not existed:
        os.remove(path)
    return path


def writable_folder(name: str, path, create: bool = True) -> str:
    """A folder that results can be written into, created now: checked before the work whose
    results go there. create=False: not created yet (by the caller, once its input is checked),
    so a refused input leaves no folder behind; the nearest existing folder above it must be
    writable."""
    if not isinstance(path, (str, os.PathLike)) or not os.fspath(path):
        raise ValueError(f"{name}: expected a folder path, got {path!r}")
    path = os.fspath(path)
    if os.path.exists(path) and not os.path.isdir(path):
        raise ValueError(f"{name}: '{path}' exists and is not a folder")
    if not create and not os.path.exists(path):
        above = os.path.dirname(os.path.abspath(path))
        while not os.path.exists(above):
            above = os.path.dirname(above)
        if not os.path.isdir(above) or not os.access(above, os.W_OK | os.X_OK):
            raise ValueError(f"{name}: cannot create folder '{path}' ('{above}' is not a writable folder)")
        return path
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as e:
        raise ValueError(f"{name}: cannot create folder '{path}' ({e.strerror or e})") from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise ValueError(f"{name}: cannot write into folder '{path}'")
    return path


def _real_array(name: str, value) -> np.ndarray:
    if isinstance(value, (str, bytes)) or value is None:
        raise ValueError(f"{name}: expected an array of coordinates, got {type(value).__name__}")
    try:
        a = np.asarray(value)
    except (ValueError, TypeError) as e:  # ragged nested lists
        raise ValueError(f"{name}: not a rectangular array ({e})") from None
    if a.dtype.kind not in "fiu":  # complex would lose its imaginary part, objects and strings are no coordinates
        raise ValueError(f"{name}: expected real coordinates, got dtype {a.dtype}")
    # longdouble, or integers beyond 2^53: converting must not move a coordinate (the queries'
    # answers are exact for the doubles they get); the API's own conversion
    from conecull._api import _as_float64

    return _as_float64(a, name)


def _first_non_finite(a: np.ndarray) -> str:
    idx = tuple(int(i) for i in np.argwhere(~np.isfinite(a))[0])
    where = f"row {idx[-2]}, column {idx[-1]}"
    return f"non-finite coordinate {a[idx]} at {where}" if a.ndim == 2 else \
        f"frame {idx[0]} has a non-finite coordinate {a[idx]} at {where}"


def first_out_of_range(a: np.ndarray, of: str = "") -> str | None:
    """The first coordinate the queries refuse (_api.RANGE_RULE), said here so that a file's
    coordinate is refused with the file named."""
    from conecull._api import RANGE_RULE, _outside_range

    bad = _outside_range(a)
    if not bad.any():
        return None
    idx = tuple(int(i) for i in np.argwhere(bad)[0])
    where = f"at row {idx[-2]}, column {idx[-1]}" if a.ndim == 2 else f"in frame {idx[0]} at row {idx[-2]}, column {idx[-1]}"
    return f"coordinate {float(a[idx])!r} {where}{of} is outside the supported range: {RANGE_RULE} (rescale the mesh)"


def points(name: str, value) -> np.ndarray:
    """Positions (n, 3), real, finite and within the queries' range, as float64."""
    a = _real_array(name, value)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name}: expected an array of shape (n, 3), got {a.shape}")
    if not np.isfinite(a).all():
        raise ValueError(f"{name}: {_first_non_finite(a)}")
    if (why := first_out_of_range(a)) is not None:
        raise ValueError(f"{name}: {why}")
    return a


def frames(name: str, value, n_vertices: int | None = None, source: str | None = None) -> np.ndarray:
    """A sequence of poses (T, n, 3) with T >= 1 and n >= 1, real, finite and within the queries'
    range, as float64.
    `source` (a file) is named in the messages too; `n_vertices`, if given, is the mesh's."""
    of = f" in '{source}'" if source else ""
    a = _real_array(name, value)
    if a.ndim == 2 and a.shape[-1:] == (3,):
        raise ValueError(f"{name}: expected a sequence of frames of shape (T, n, 3){of}, got one pose of shape "
                         f"{a.shape}; pass it as [V] (or V[None]) for a one-frame sequence")
    if a.ndim != 3 or a.shape[2] != 3:
        raise ValueError(f"{name}: expected an array of shape (T, n, 3){of}, got {a.shape}")
    if a.shape[0] == 0:
        raise ValueError(f"{name}: no frames{of} (shape {a.shape}); need at least one")
    if n_vertices is not None and a.shape[1] != n_vertices:
        raise ValueError(f"{name}: frames have {a.shape[1]} vertices{of} but the mesh has {n_vertices}")
    if a.shape[1] == 0:
        raise ValueError(f"{name}: frames have no vertices{of} (shape {a.shape})")
    if not np.isfinite(a).all():
        raise ValueError(f"{name}: {_first_non_finite(a)}{of}")
    if (why := first_out_of_range(a, of)) is not None:
        raise ValueError(f"{name}: {why}")
    return a
