"""python/granflow/statistics.py (the C++ lib/statistics through ctypes) against the
same algorithms written with numpy, kept here as the reference oracle: the blocking errors,
the halves change and the block jackknife must be the same floats bit for bit
(assertEqual), MSER the same truncation, on many random series (AR(1), white noise, ramps,
constant series, lengths 32..5000 and a few longer ones past numpy's 8192-value chunks);
and the make rules that remake the tables when the library changes."""
import math
import os
import re
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

from granflow import statistics as st
from synthetic import scratch_make

MIN_SAMPLES = 32
MIN_BLOCKS = 16
TRANSIENT_BLOCKS = 100


# ---- the algorithms written with numpy, the oracle ----


def _chi2_99(dof):
    z = 2.3263478740408408
    return dof * (1 - 2 / (9 * dof) + z * math.sqrt(2 / (9 * dof))) ** 3


def oracle_blocking_error(x):
    x = np.asarray(x, dtype=float)
    if len(x) < MIN_SAMPLES:
        raise ValueError(f"blocking needs at least {MIN_SAMPLES} samples, got {len(x)}")
    se2, n, stat = [], [], []
    while len(x) >= 2:
        if len(x) % 2:
            x = x[1:]
        m = len(x)
        d = x - x.mean()
        var = np.mean(d * d)
        se2.append(var / (m - 1))
        n.append(m)
        stat.append(0.0 if var == 0 else m * ((m - 1) * var / m**2 + np.mean(d[:-1] * d[1:])) ** 2 / var**2)
        x = 0.5 * (x[0::2] + x[1::2])
    levels = len(se2)
    tail = np.cumsum(stat[::-1])[::-1]
    usable = max(j for j in range(levels) if n[j] >= MIN_BLOCKS)
    for j in range(usable + 1):
        if tail[j] < _chi2_99(levels - j):
            j = min(j + 1, usable)
            return math.sqrt(se2[j]), n[j], True
    return math.sqrt(se2[usable]), n[usable], False


def oracle_mser_truncation(x):
    x = np.asarray(x, dtype=float)
    n = len(x)
    if n < 2:
        return 0
    d = x - x.mean()
    s1 = np.cumsum(d[::-1])[::-1]
    s2 = np.cumsum((d * d)[::-1])[::-1]
    m = n - np.arange(n // 2 + 1)
    stat = np.maximum(0.0, s2[: n // 2 + 1] - s1[: n // 2 + 1] ** 2 / m) / m**2
    return int(np.argmin(stat))


def oracle_first_row(series):
    """MSER on block means of numpy (mean(axis=1)), as a row."""
    rows = max(1, len(series[0]) // TRANSIENT_BLOCKS)
    blocks = len(series[0]) // rows
    d = 0
    for x in series:
        d = max(d, oracle_mser_truncation(np.asarray(x)[: blocks * rows].reshape(blocks, rows).mean(axis=1)))
    return d * rows


def oracle_halves_change(x):
    x = np.asarray(x, dtype=float)
    half = len(x) // 2
    first, second = x[:half], x[len(x) - half :]
    return (
        float(np.mean(second) - np.mean(first)),
        math.hypot(oracle_blocking_error(first)[0], oracle_blocking_error(second)[0]),
    )


def oracle_jackknife_errors(blocks, estimate):
    """lib/statistics/jackknife.hpp in Python floats, in its order: each block left out in
    turn, the others added element-wise starting from the first one kept; the mean of the
    left-out estimates summed in order, each divided by B; error = √((B−1)/B · Σ(x − x̄)²)."""
    blocks = [np.asarray(b, dtype=float) for b in blocks]
    n = len(blocks)
    if n < 2:
        return [math.nan] * len(estimate(blocks[0]))
    left_out = []
    for b in range(n):
        first = 1 if b == 0 else 0
        others = blocks[first].copy()
        for k in range(n):
            if k not in (b, first):
                others += blocks[k]
        left_out.append([float(v) for v in estimate(others)])
    errors = []
    for c in range(len(left_out[0])):
        mean = 0.0
        for x in left_out:
            mean += x[c] / n
        sum2 = 0.0
        for x in left_out:
            sum2 += (x[c] - mean) * (x[c] - mean)
        errors.append(math.sqrt((n - 1) / n * sum2))
    return errors


# ---- random series ----


def ar1(rng, n, phi, mean=0.0, scale=1.0):
    x = np.empty(n)
    x[0] = rng.normal() / math.sqrt(1 - phi * phi)
    eps = rng.normal(size=n)
    for i in range(1, n):
        x[i] = phi * x[i - 1] + eps[i]
    return mean + scale * x


def series_zoo(seed, count):
    """`count` random series of the kinds the tables see and a few they should survive."""
    rng = np.random.default_rng(seed)
    special = [32, 33, 63, 64, 65, 127, 128, 129, 255, 256, 257, 1000, 4095, 4096, 4097, 5000]
    out = []
    for k in range(count):
        n = special[k] if k < len(special) else int(rng.integers(32, 5001))
        kind = k % 6
        if kind == 0:
            x = ar1(
                rng,
                n,
                float(rng.choice([0.3, 0.7, 0.9, 0.99, 0.999])),
                mean=rng.uniform(-10, 10),
                scale=10.0 ** rng.uniform(-6, 3),
            )
        elif kind == 1:
            x = rng.normal(rng.uniform(-1e3, 1e3), 10.0 ** rng.uniform(-8, 2), n)  # white noise on an offset
        elif kind == 2:
            x = rng.uniform(0, 1, n) * 10.0 ** rng.uniform(-3, 3)
        elif kind == 3:
            x = np.linspace(rng.uniform(-5, 5), rng.uniform(-5, 5), n) + rng.normal(0, rng.uniform(0, 0.5), n)  # ramp
        elif kind == 4:
            # A transient decaying into noise, like T of a run sheared from rest.
            t = np.arange(n)
            x = 1 + 5 * np.exp(-t / rng.uniform(5, n / 3)) + ar1(rng, n, 0.8, scale=0.05)
        else:
            x = np.full(n, float(rng.choice([0.0, 2.5, 0.1, 1 / 3, -7.3e5, 1e-300])))  # constant
        out.append(x)
    return out


class NumpySumTest(unittest.TestCase):
    """The library sums in numpy's order: the means below depend on it."""

    def test_equals_np_sum(self):
        rng = np.random.default_rng(1)
        for n in list(range(0, 1001)) + [8191, 8192, 8193, 16385, 20000, 100001]:
            x = rng.normal(size=n) * np.exp(rng.uniform(-20, 20, n))
            self.assertEqual(st.numpy_sum(x), float(np.sum(x)), n)


class BitIdentityTest(unittest.TestCase):
    def test_blocking_error(self):
        for x in series_zoo(11, 400):
            self.assertEqual(st.blocking_error(x), oracle_blocking_error(x), len(x))

    def test_blocking_error_long_series(self):
        rng = np.random.default_rng(12)
        for n in (8192, 8193, 16384 + 33, 40000, 100000):
            for phi in (0.0, 0.95):
                x = ar1(rng, n, phi, mean=3.0)
                self.assertEqual(st.blocking_error(x), oracle_blocking_error(x), (n, phi))

    def test_halves_change(self):
        for x in series_zoo(13, 400):
            if len(x) // 2 >= MIN_SAMPLES:
                self.assertEqual(st.halves_change(x), oracle_halves_change(x), len(x))

    def test_mser(self):
        # The library's MSER sums in order where the oracle's mean was numpy's pairwise sum:
        # equal truncations still, constant series included (their rounding noise alike).
        for x in series_zoo(14, 400):
            self.assertEqual(st.mser_truncation(x), oracle_mser_truncation(x), len(x))
        self.assertEqual(st.mser_truncation([3.0]), 0)
        self.assertEqual(st.mser_truncation([]), 0)

    def test_first_row(self):
        zoo = series_zoo(15, 400)
        for a, b in zip(zoo[0::2], zoo[1::2]):
            n = min(len(a), len(b))
            self.assertEqual(st.mser_first_row([a[:n], b[:n]], TRANSIENT_BLOCKS), oracle_first_row([a[:n], b[:n]]), n)
        self.assertEqual(st.mser_first_row([]), 0)


class JackknifeTest(unittest.TestCase):
    """jackknife_errors through the C API's estimator callback, against the oracle above."""

    @staticmethod
    def ratio_and_sum(s):
        return [s[0] / s[1], s[2], s[0] * s[2] / (s[1] * s[1])]

    def test_bit_identical_to_the_oracle(self):
        rng = np.random.default_rng(46)
        for count in (2, 3, 7, 16, 100):
            blocks = rng.uniform(0.5, 2.0, size=(count, 3)) * 10.0 ** rng.uniform(-3, 3, size=3)
            with self.subTest(blocks=count):
                got = st.jackknife_errors(blocks, self.ratio_and_sum)
                self.assertIs(type(got), np.ndarray)
                self.assertEqual(got.tolist(), oracle_jackknife_errors(blocks, self.ratio_and_sum))

    def test_linear_estimator_is_the_standard_error_of_the_block_means(self):
        # For the mean of block values, the jackknife error is the plain standard error.
        x = np.random.default_rng(7).normal(size=(40, 1))
        got = st.jackknife_errors(np.column_stack((x, np.ones(40))), lambda s: [s[0] / s[1]])
        self.assertAlmostEqual(got[0], float(np.std(x, ddof=1) / math.sqrt(40)), places=12)

    def test_edges(self):
        self.assertTrue(np.isnan(st.jackknife_errors([[1.0, 2.0]], lambda s: [s[0], s[1]])).all())
        self.assertEqual(len(st.jackknife_errors(np.ones((4, 2)), lambda s: [])), 0)
        # Leaving out the last block leaves s[1] = 0: that component's error is NaN.
        nan = st.jackknife_errors(
            [[1.0, 0.0], [1.0, 0.0], [2.0, 1.0]], lambda s: [s[0] / s[1] if s[1] else math.nan, s[0]]
        )
        self.assertTrue(math.isnan(nan[0]))
        self.assertTrue(math.isfinite(nan[1]))
        with self.assertRaisesRegex(ValueError, "at least one block"):
            st.jackknife_errors(np.zeros((0, 2)), lambda s: [s[0]])
        with self.assertRaisesRegex(ValueError, "2-D"):
            st.jackknife_errors([1.0, 2.0], lambda s: [s[0]])

    def test_estimator_errors_are_raised_again(self):
        def fails(s):
            if s[0] > 2:
                raise ZeroDivisionError("from the estimator")
            return [s[0]]

        with self.assertRaisesRegex(ZeroDivisionError, "from the estimator"):
            st.jackknife_errors(np.ones((4, 1)), fails)
        calls = []

        def changes_length(s):
            calls.append(1)
            return [s[0]] * len(calls)

        with self.assertRaisesRegex(ValueError, "estimate returned 2 values, and 1 before"):
            st.jackknife_errors(np.ones((4, 1)), changes_length)


class InterfaceTest(unittest.TestCase):
    def test_too_few_samples(self):
        with self.assertRaisesRegex(ValueError, "^blocking needs at least 32 samples, got 31$"):
            st.blocking_error(np.ones(31))
        with self.assertRaisesRegex(ValueError, "^blocking needs at least 32 samples, got 31$"):
            st.halves_change(np.ones(63))
        self.assertEqual(st.blocking_error(np.ones(32)), (0.0, 16, True))

    def test_types_and_inputs(self):
        err, blocks, plateau = st.blocking_error(list(range(100)))
        self.assertIs(type(err), float)
        self.assertIs(type(blocks), int)
        self.assertIs(type(plateau), bool)
        x = np.arange(200.0)[::2]  # a strided view is copied, not misread
        self.assertEqual(st.blocking_error(x), oracle_blocking_error(x))
        with self.assertRaises(ValueError):
            st.blocking_error(np.ones((40, 2)))

    def test_missing_library_names_the_path_and_the_build_command(self):
        code = (
            "from granflow import statistics as st\n"
            "try:\n    st.blocking_error([1.0] * 40)\n"
            "except st.LibraryMissing as e:\n    print(e)\n"
        )
        env = dict(os.environ, GRANFLOW_BUILD="/nonexistent/build")
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True).stdout
        self.assertIn("/nonexistent/build/lib/libgranflow_statistics.so", out)
        self.assertIn("make -f Makefile.sweeps build", out)


class LibraryStampTest(unittest.TestCase):
    """Tables made with the library are remade when its machine code changes: their make
    rules have the library's stamp (build/stamps/libgranflow_statistics.so.stamp) as a
    prerequisite, and nothing else is redone (SIZE=test, files faked with ordered times)."""

    ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

    def test_tables_follow_the_library_stamp(self):
        for table in ("ch4_sweep.h5", "ch4_critical_angle.h5"):
            with self.subTest(table=table), tempfile.TemporaryDirectory() as d:
                make = scratch_make(d)
                stamps = [
                    f"{d}/build/stamps/{p}.stamp"
                    for p in ("gf-pack", "gf-shear", "gf-incline", "gf-correlate", "libgranflow_statistics.so")
                ]
                os.makedirs(f"{d}/build/stamps")
                os.makedirs(f"{d}/runs")
                for path in stamps:
                    open(path, "w").close()
                    os.utime(path, (1000, 1000))
                target = f"{d}/runs/{table}"
                plan = subprocess.run(
                    make + ["-n", target], cwd=self.ROOT, capture_output=True, text=True, check=True
                ).stdout
                # Every simulation's output, in the order made; then the table, newer than the sources.
                outputs = re.findall(r" -o (\S+)", plan)
                self.assertEqual(outputs[-1], target, plan)
                now = time.time()  # the table is newer than the sources, made a second ago
                for k, path in enumerate(outputs):
                    open(path, "w").close()
                    t = 2000 + k if path != target else now - 1
                    os.utime(path, (t, t))
                self.assertEqual(subprocess.run(make + ["-q", target], cwd=self.ROOT).returncode, 0)
                os.utime(stamps[-1], (now, now))  # the library's code changed: its stamp was rewritten
                self.assertEqual(subprocess.run(make + ["-q", target], cwd=self.ROOT).returncode, 1)
                plan = subprocess.run(
                    make + ["-n", target], cwd=self.ROOT, capture_output=True, text=True, check=True
                ).stdout
                self.assertEqual(re.findall(r" -o (\S+)", plan), [target], plan)


if __name__ == "__main__":
    unittest.main()
