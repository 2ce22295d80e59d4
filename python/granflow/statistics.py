"""The steady-state rule and the error estimators of lib/statistics (C++), for Python: one
implementation for the programs, the pipelines' tables and users (docs/method/statistics.md).

Loaded with ctypes from the shared library libgranflow_statistics.so, at the first call (so
that importing this module needs no library), from the first of:

1. $GRANFLOW_BUILD/lib when GRANFLOW_BUILD is set (a CMake build directory; Makefile.sweeps
   and ctest set it, so the pipelines use the library whose stamp their tables depend on);
2. the package's own directory, where `pip install ./python` builds it;
3. <repo>/build/lib when the package is used from the repository (PYTHONPATH=<repo>/python),
   the default CMake build directory (`make -f Makefile.sweeps build` makes it).

library_path() says which it is.

- mser_truncation(x): MSER's truncation point d <= len(x)//2 (White 1997).
- mser_first_row(series, blocks=100): the first row of the steady part of per-row series
  (MSER on block means, the latest wins), as gf-correlate --detect-transient finds it.
- blocking_error(x) -> (error, blocks, plateau): standard error of the mean by
  Flyvbjerg-Petersen blocking with Jonsson's plateau choice (lib/statistics/blocking.hpp).
- halves_change(x) -> (change, error): mean of the second half minus the first, with
  blocking errors (the stationarity test of the shear tables).
- jackknife_errors(blocks, estimate): block-jackknife standard errors of an estimator of
  sums over blocks (lib/statistics/jackknife.hpp, as gf-correlate uses it).
- numpy_sum(x): the library's sum, in numpy's pairwise order.
The floats equal bit for bit those of the same algorithm written with numpy (the library
sums in numpy's pairwise order and rounds hypot as math.hypot), checked by
pipelines/tests/test_statistics.py.
"""
import ctypes
import os

import numpy as np

LIBRARY_NAME = "libgranflow_statistics.so"
ABI_VERSION = 2
MIN_SAMPLES = 32  # blocking's minimum, checked against the library at load time

_OK, _TOO_FEW_SAMPLES, _BAD_ARGUMENT = 0, 1, 2
_PACKAGE = os.path.dirname(os.path.abspath(__file__))
_REPO = os.path.dirname(os.path.dirname(_PACKAGE))
_library = None
# The estimator callback of gf_stat_jackknife_errors (lib/statistics/c_api.h).
_ESTIMATOR = ctypes.CFUNCTYPE(
    ctypes.c_int,
    ctypes.POINTER(ctypes.c_double),
    ctypes.c_size_t,
    ctypes.POINTER(ctypes.c_double),
    ctypes.c_size_t,
    ctypes.c_void_p,
)


class LibraryMissing(RuntimeError):
    """The statistics library is not built (or not where GRANFLOW_BUILD says), or is from
    another version of granflow."""


def _in_repository():
    # The package's source directory <repo>/python/granflow, not an installed copy.
    return os.path.isfile(os.path.join(_REPO, "lib", "statistics", "c_api.h"))


def library_path():
    """Where the shared library is looked for: $GRANFLOW_BUILD/lib if GRANFLOW_BUILD is set;
    else the package's directory if the library is there (an installed package); else
    <repo>/build/lib (the package used from the repository)."""
    build = os.environ.get("GRANFLOW_BUILD")
    if build:
        return os.path.join(os.path.abspath(build), "lib", LIBRARY_NAME)
    bundled = os.path.join(_PACKAGE, LIBRARY_NAME)
    if os.path.exists(bundled) or not _in_repository():
        return bundled
    return os.path.join(_REPO, "build", "lib", LIBRARY_NAME)


def _remedy():
    if os.environ.get("GRANFLOW_BUILD") or _in_repository():
        return (
            "build it with `make -f Makefile.sweeps build` (or set GRANFLOW_BUILD to the CMake build "
            f"directory that has lib/{LIBRARY_NAME})"
        )
    return "reinstall the package (`pip install <repo>/python`, docs/python.md), which builds it"


def _load():
    global _library
    if _library is not None:
        return _library
    path = library_path()
    try:
        lib = ctypes.CDLL(path)
    except OSError as exc:
        raise LibraryMissing(f"granflow statistics library not found at {path} ({exc}); {_remedy()}") from None
    size_p, double_p = ctypes.POINTER(ctypes.c_size_t), ctypes.POINTER(ctypes.c_double)
    array = np.ctypeslib.ndpointer(dtype=np.float64, flags="C_CONTIGUOUS")
    lib.gf_stat_abi_version.restype = ctypes.c_int
    lib.gf_stat_abi_version.argtypes = []
    lib.gf_stat_blocking_min_samples.restype = ctypes.c_size_t
    lib.gf_stat_blocking_min_samples.argtypes = []
    # Checked first: an older library lacks functions bound below.
    if lib.gf_stat_abi_version() != ABI_VERSION or lib.gf_stat_blocking_min_samples() != MIN_SAMPLES:
        raise LibraryMissing(
            f"{path} is from another version of granflow (ABI {lib.gf_stat_abi_version()}, "
            f"expected {ABI_VERSION}); {_remedy().replace('build it', 'rebuild it', 1)}"
        )
    lib.gf_stat_mser_truncation.argtypes = [array, ctypes.c_size_t, size_p]
    lib.gf_stat_mser_first_row.argtypes = [array, ctypes.c_size_t, ctypes.c_size_t, ctypes.c_size_t, size_p]
    lib.gf_stat_blocking_error.argtypes = [array, ctypes.c_size_t, double_p, size_p, ctypes.POINTER(ctypes.c_int)]
    lib.gf_stat_halves_change.argtypes = [array, ctypes.c_size_t, double_p, double_p]
    lib.gf_stat_numpy_sum.argtypes = [array, ctypes.c_size_t, double_p]
    lib.gf_stat_jackknife_errors.argtypes = [
        array,
        ctypes.c_size_t,
        ctypes.c_size_t,
        ctypes.c_size_t,
        _ESTIMATOR,
        ctypes.c_void_p,
        array,
    ]
    for name in ("mser_truncation", "mser_first_row", "blocking_error", "halves_change", "numpy_sum"):
        getattr(lib, "gf_stat_" + name).restype = ctypes.c_int
    lib.gf_stat_jackknife_errors.restype = ctypes.c_int
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


def _doubles(pointer, n):
    # n doubles at a C pointer as a numpy view (empty without touching the pointer when n = 0).
    return np.ctypeslib.as_array(pointer, shape=(n,)) if n else np.zeros(0)


def jackknife_errors(blocks, estimate):
    """Block-jackknife standard errors of an estimator of sums, for estimators nonlinear in
    sums over frames (ratios such as gf-correlate's C = Σw/W), where blocking a series does
    not apply.

    blocks: 2-D array-like, row b the sums of block b (consecutive frames, longer than the
    correlation time). estimate: a function of one 1-D float array of sums (a row, or rows
    added) returning a 1-D array-like of estimates, the same length each time. The estimator
    is recomputed with each block left out (the others added element-wise, in the library's
    order), and per component error² = (B − 1)/B · Σ_b (x_(b) − x̄)², x̄ the mean of the x_(b).
    Returns a float array of the errors (NaN with a single block, or where a left-out value
    is NaN); ValueError without a block; an exception of `estimate` is raised again."""
    lib = _load()
    data = np.ascontiguousarray(np.asarray(blocks, dtype=np.float64))
    if data.ndim != 2:
        raise ValueError(f"expected blocks of sums (2-D), got shape {data.shape}")
    count, width = data.shape
    if count == 0:
        raise ValueError("jackknife_errors needs at least one block")
    components = len(np.asarray(estimate(data[0].copy()), dtype=np.float64).reshape(-1))
    failure = []

    def call(sums, sums_width, out, out_components, _context):
        try:
            value = np.asarray(estimate(_doubles(sums, sums_width).copy()), dtype=np.float64).reshape(-1)
            if len(value) != out_components:
                raise ValueError(f"estimate returned {len(value)} values, and {out_components} before")
            _doubles(out, out_components)[:] = value
            return 0
        except BaseException as exc:  # noqa: B036  (raised again below, after the library returns)
            failure.append(exc)
            return 1

    errors = np.zeros(max(components, 1))
    code = lib.gf_stat_jackknife_errors(
        data.reshape(-1) if data.size else np.zeros(1), count, width, components, _ESTIMATOR(call), None, errors
    )
    if failure:
        raise failure[0]
    _check(code, "jackknife_errors")
    return errors[:components].copy()
