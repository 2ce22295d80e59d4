"""The steady-state rule and the error estimators of lib/statistics (C++), for the Python
pipelines: one implementation for the programs and the tables (docs/method/statistics.md).

Loaded with ctypes from the shared library libgranflow_statistics.so, which the default
build target makes (`make -f Makefile.sweeps build`), in $GRANFLOW_BUILD/lib (the CMake
build directory; <repo>/build by default). The library is loaded at the first call, so
that scripts importing this module only for its neighbours need no build.

- mser_truncation(x): MSER's truncation point d <= len(x)//2 (White 1997).
- mser_first_row(series, blocks=100): the first row of the steady part of per-row series
  (MSER on block means, the latest wins), as gf-correlate --detect-transient finds it.
- blocking_error(x) -> (error, blocks, plateau): standard error of the mean by
  Flyvbjerg-Petersen blocking with Jonsson's plateau choice (lib/statistics/blocking.hpp).
- halves_change(x) -> (change, error): mean of the second half minus the first, with
  blocking errors (the stationarity test of the shear tables).
The floats equal bit for bit those of the same algorithm written with numpy (the library
sums in numpy's pairwise order and rounds hypot as math.hypot), checked by
pipelines/tests/test_statistics.py.
"""
import ctypes
import os

import numpy as np

LIBRARY_NAME = "libgranflow_statistics.so"
ABI_VERSION = 1
MIN_SAMPLES = 32  # blocking's minimum, checked against the library at load time

_OK, _TOO_FEW_SAMPLES, _BAD_ARGUMENT = 0, 1, 2
_REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
_library = None


class LibraryMissing(RuntimeError):
    """The statistics library is not built (or not where GRANFLOW_BUILD says)."""


def library_path():
    """Where the shared library is looked for: $GRANFLOW_BUILD/lib, default <repo>/build/lib."""
    build = os.environ.get("GRANFLOW_BUILD") or os.path.join(_REPO, "build")
    return os.path.join(os.path.abspath(build), "lib", LIBRARY_NAME)


def _load():
    global _library
    if _library is not None:
        return _library
    path = library_path()
    try:
        lib = ctypes.CDLL(path)
    except OSError as exc:
        raise LibraryMissing(
            f"granflow statistics library not found at {path} ({exc}); build it with "
            f"`make -f Makefile.sweeps build` (or set GRANFLOW_BUILD to the CMake build "
            f"directory that has lib/{LIBRARY_NAME})"
        ) from None
    size_p, double_p = ctypes.POINTER(ctypes.c_size_t), ctypes.POINTER(ctypes.c_double)
    array = np.ctypeslib.ndpointer(dtype=np.float64, flags="C_CONTIGUOUS")
    lib.gf_stat_abi_version.restype = ctypes.c_int
    lib.gf_stat_abi_version.argtypes = []
    lib.gf_stat_blocking_min_samples.restype = ctypes.c_size_t
    lib.gf_stat_blocking_min_samples.argtypes = []
    lib.gf_stat_mser_truncation.argtypes = [array, ctypes.c_size_t, size_p]
    lib.gf_stat_mser_first_row.argtypes = [array, ctypes.c_size_t, ctypes.c_size_t, ctypes.c_size_t, size_p]
    lib.gf_stat_blocking_error.argtypes = [array, ctypes.c_size_t, double_p, size_p, ctypes.POINTER(ctypes.c_int)]
    lib.gf_stat_halves_change.argtypes = [array, ctypes.c_size_t, double_p, double_p]
    lib.gf_stat_numpy_sum.argtypes = [array, ctypes.c_size_t, double_p]
    for name in ("mser_truncation", "mser_first_row", "blocking_error", "halves_change", "numpy_sum"):
        getattr(lib, "gf_stat_" + name).restype = ctypes.c_int
    if lib.gf_stat_abi_version() != ABI_VERSION or lib.gf_stat_blocking_min_samples() != MIN_SAMPLES:
        raise LibraryMissing(
            f"{path} is from another version of granflow (ABI {lib.gf_stat_abi_version()}, "
            f"expected {ABI_VERSION}); rebuild it with `make -f Makefile.sweeps build`"
        )
    _library = lib
    return lib


def _values(x):
    # A contiguous float64 copy only when needed; a 1-D array of at least one element so
    # that ctypes always has a valid pointer.
    x = np.ascontiguousarray(x, dtype=np.float64)
    if x.ndim != 1:
        raise ValueError(f"expected a 1-D series, got shape {x.shape}")
    return x, len(x)


def _check(code, what):
    if code == _BAD_ARGUMENT:
        raise ValueError(f"{what}: bad argument")
    if code != _OK:
        raise RuntimeError(f"{what} failed (code {code})")


def _blocking_too_short(n):
    return ValueError(f"blocking needs at least {MIN_SAMPLES} samples, got {n}")


def mser_truncation(x):
    """MSER: the d <= len(x)//2 minimising the variance of x[d:] over (len(x) - d)^2, the
    first on ties; 0 for fewer than 2 values."""
    lib = _load()
    x, n = _values(x)
    out = ctypes.c_size_t()
    _check(lib.gf_stat_mser_truncation(x if n else np.zeros(1), n, ctypes.byref(out)), "mser_truncation")
    return int(out.value)


def mser_first_row(series, blocks=100):
    """First row of the steady part of per-row series of equal length: each cut into
    `blocks` blocks of max(1, rows // blocks) rows (rows left over at the end in none), MSER
    on each one's block means, the latest truncation wins, returned as a row (0 when empty)."""
    lib = _load()
    if len(series) == 0:
        return 0
    data = np.ascontiguousarray(np.asarray(series, dtype=np.float64))
    if data.ndim != 2:
        raise ValueError(f"expected equal-length series (2-D), got shape {data.shape}")
    count, length = data.shape
    out = ctypes.c_size_t()
    code = lib.gf_stat_mser_first_row(
        data.reshape(-1) if data.size else np.zeros(1), count, length, int(blocks), ctypes.byref(out)
    )
    _check(code, "mser_first_row")
    return int(out.value)


def blocking_error(x):
    """(standard error of mean(x), blocks at the chosen level, plateau found) by
    Flyvbjerg-Petersen blocking with Jonsson's automatic choice of the level; ValueError
    with fewer than MIN_SAMPLES values."""
    lib = _load()
    x, n = _values(x)
    if n < MIN_SAMPLES:
        raise _blocking_too_short(n)
    error, blocks, plateau = ctypes.c_double(), ctypes.c_size_t(), ctypes.c_int()
    code = lib.gf_stat_blocking_error(x, n, ctypes.byref(error), ctypes.byref(blocks), ctypes.byref(plateau))
    if code == _TOO_FEW_SAMPLES:
        raise _blocking_too_short(n)
    _check(code, "blocking_error")
    return float(error.value), int(blocks.value), bool(plateau.value)


def halves_change(x):
    """(mean of the second half of x - mean of the first, its error), each half's error by
    blocking (an odd count's middle value in neither half); ValueError when a half has fewer
    than MIN_SAMPLES values."""
    lib = _load()
    x, n = _values(x)
    if n // 2 < MIN_SAMPLES:
        raise _blocking_too_short(n // 2)
    change, error = ctypes.c_double(), ctypes.c_double()
    code = lib.gf_stat_halves_change(x, n, ctypes.byref(change), ctypes.byref(error))
    if code == _TOO_FEW_SAMPLES:
        raise _blocking_too_short(n // 2)
    _check(code, "halves_change")
    return float(change.value), float(error.value)


def numpy_sum(x):
    """The library's sum in numpy's pairwise order (the order of its means); equals np.sum(x)."""
    lib = _load()
    x, n = _values(x)
    out = ctypes.c_double()
    _check(lib.gf_stat_numpy_sum(x if n else np.zeros(1), n, ctypes.byref(out)), "numpy_sum")
    return float(out.value)
