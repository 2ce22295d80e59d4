"""Tests of pipelines/analysis/steady_state.py on synthetic trajectories with known answers:
block-averaging errors against the exact standard error of AR(1) series, the transient
skip (fixed, and found from the run), the thesis' normalisations on a constructed run, and the
table the CLI writes."""
import glob
import hashlib
import os
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

from analysis import steady_state as ss

import synthetic  # a sibling module: the tests' own fixtures

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "analysis", "steady_state.py")


class BlockingTest(unittest.TestCase):
    def test_white_noise_error_is_sigma_over_sqrt_n(self):
        rng = np.random.default_rng(7)
        x = rng.normal(3.0, 2.0, 4096)
        err, blocks, plateau = ss.blocking_error(x)
        self.assertTrue(plateau)
        self.assertAlmostEqual(err / (2.0 / np.sqrt(4096)), 1.0, delta=0.15)

    def test_ar1_error_within_factor_1_5_of_exact(self):
        for phi in (0.5, 0.9, 0.98):
            n = 20000
            exact = synthetic.ar1_mean_se(phi, n)
            ratios = []
            for seed in range(8):
                x = synthetic.ar1(phi, n, np.random.default_rng(seed))
                err, _, plateau = ss.blocking_error(x)
                self.assertTrue(plateau, f"phi={phi} seed={seed}")
                ratios.append(err / exact)
                with self.subTest(phi=phi, seed=seed):
                    self.assertLess(max(err / exact, exact / err), 1.5)
            with self.subTest(phi=phi):
                self.assertAlmostEqual(np.mean(ratios), 1.0, delta=0.15)
        # The naive error ignores the correlation and would be far too small.
        x = synthetic.ar1(0.9, n, np.random.default_rng(0))
        self.assertLess(np.std(x) / np.sqrt(n) / synthetic.ar1_mean_se(0.9, n), 0.3)

    def test_too_short_series_is_flagged(self):
        x = synthetic.ar1(0.999, 2000, np.random.default_rng(3))
        self.assertFalse(ss.blocking_error(x)[2])

    def test_too_few_samples_is_an_error(self):
        with self.assertRaises(ValueError):
            ss.blocking_error(np.ones(ss.MIN_SAMPLES - 1))


class RunTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)

    def path(self, name):
        return os.path.join(self.tmp.name, name)

    def test_normalisations_on_a_constructed_run(self):
        n, rate = 400, 2.0
        ps, pk, s, temp = (np.full(n, v) for v in (3.0, 1.0, 1.2, 0.5))
        synthetic.write_run(self.path("c.h5"), ps, pk, s, temp, rate=rate, n1=0.02)
        run = ss.read_run(self.path("c.h5"))
        m, r = run["parameters"]["mean_mass"], run["parameters"]["mean_radius"]
        values, _, samples = ss.steady_values(run, 0.0)
        expected = {
            "pressure": 4.0,
            "shear_stress": 1.2,
            "temperature": 0.5,
            "pressure_static": 3.0,
            "pressure_kinetic": 1.0,
            "pressure_collisional": 2.7,
            "normal_stress_difference": 0.02,
            "pressure_scaled": 4.0 / (rate**2 * m),
            "shear_stress_scaled": 1.2 / (rate**2 * m),
            "temperature_scaled": 0.5 / (rate**2 * r**2),
            "pressure_static_scaled": 3.0 / (rate**2 * m),
            "pressure_kinetic_scaled": 1.0 / (rate**2 * m),
            "pressure_collisional_scaled": 2.7 / (rate**2 * m),
            "s_over_p": 0.3,
            "rate_R_over_sqrt_T": rate * r / np.sqrt(0.5),
            "mT_over_pR2": m * 0.5 / (4.0 * r**2),
        }
        self.assertEqual(set(expected), set(ss.QUANTITIES))
        self.assertEqual(samples, n)
        for name, value in expected.items():
            with self.subTest(name=name):
                self.assertAlmostEqual(values[name][0], value, delta=1e-12 * abs(value))
                self.assertLess(values[name][1], 1e-12 * abs(value))

    def test_ratio_error_keeps_the_correlation(self):
        # s = 0.3 p at every step: s/p is exactly 0.3 however much p fluctuates.
        rng = np.random.default_rng(1)
        p = 10 + 2 * synthetic.ar1(0.9, 4000, rng)
        synthetic.write_run(self.path("r.h5"), 0.8 * p, 0.2 * p, 0.3 * p, np.full(4000, 1.0))
        values, _, _ = ss.steady_values(ss.read_run(self.path("r.h5")), 0.0)
        self.assertAlmostEqual(values["s_over_p"][0], 0.3, delta=1e-12)
        self.assertLess(values["s_over_p"][1], 1e-12)
        self.assertGreater(values["pressure"][1], 0.05)

    def test_ratio_error_matches_the_spread_of_independent_runs(self):
        ratios, errors = [], []
        for seed in range(20):
            rng = np.random.default_rng(seed)
            p = 10 + synthetic.ar1(0.8, 4000, rng)
            s = 3 + 0.5 * synthetic.ar1(0.8, 4000, rng)
            synthetic.write_run(self.path("m.h5"), p - 1, np.ones(4000), s, np.full(4000, 1.0))
            q, err, _ = ss.steady_values(ss.read_run(self.path("m.h5")), 0.0)[0]["s_over_p"]
            ratios.append(q)
            errors.append(err)
        self.assertLess(max(np.std(ratios) / np.mean(errors), np.mean(errors) / np.std(ratios)), 1.5)

    def test_transient_before_from_strain_is_skipped(self):
        rng = np.random.default_rng(2)
        n, step = 3000, 1e-3
        strain = np.arange(1, n + 1) * step
        p = 5 + 0.5 * synthetic.ar1(0.9, n, rng)
        p[strain < 0.5] += 40 * np.exp(-strain[strain < 0.5] / 0.1)
        synthetic.write_run(self.path("t.h5"), p - 1, np.ones(n), 0.3 * p, np.full(n, 1.0), strain_step=step)
        run = ss.read_run(self.path("t.h5"))
        skipped = ss.steady_values(run, 0.5)
        kept = ss.steady_values(run, 0.0)
        value, err, _ = skipped[0]["pressure"]
        self.assertEqual(skipped[2], int(np.sum(strain >= 0.5)))
        self.assertLess(abs(value - 5), 4 * err)
        self.assertGreater(kept[0]["pressure"][0] - 5, 10 * err)

    def test_run_shorter_than_from_strain_is_an_error(self):
        synthetic.write_run(self.path("s.h5"), *(np.ones(100) for _ in range(4)))
        with self.assertRaisesRegex(ValueError, "strain >= 0.5"):
            ss.steady_values(ss.read_run(self.path("s.h5")), 0.5)

    def test_invariant_series_are_instantaneous_ratios(self):
        n = 50
        p = np.linspace(1, 2, n)
        synthetic.write_run(self.path("i.h5"), p - 0.5, np.full(n, 0.5), 0.4 * p, np.full(n, 4.0), rate=0.5)
        run = ss.read_run(self.path("i.h5"))
        inv = ss.invariant_series(run)
        m, r = run["parameters"]["mean_mass"], run["parameters"]["mean_radius"]
        np.testing.assert_allclose(inv["s_over_p"], 0.4)
        np.testing.assert_allclose(inv["rate_R_over_sqrt_T"], 0.5 * r / 2)
        np.testing.assert_allclose(inv["mT_over_pR2"], m * 4 / (p * r**2))


class TransientTest(unittest.TestCase):
    """The steady part's start found from the run (MSER on block means of T and p) and the
    stationarity check of what is averaged."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)

    def write(self, name, temperature, pressure, step=1e-3):
        path = os.path.join(self.tmp.name, name)
        synthetic.write_run(path, pressure - 1, np.ones(len(pressure)), 0.3 * pressure, temperature, strain_step=step)
        return path

    def test_mser_cuts_a_ramp(self):
        x = np.concatenate([np.linspace(0, 1, 30, endpoint=False), 1 + 1e-3 * np.sin(np.arange(70))])
        self.assertGreaterEqual(ss.mser_truncation(x), 27)
        self.assertLessEqual(ss.mser_truncation(x), 33)
        self.assertEqual(ss.mser_truncation([3.0]), 0)
        # The first of tied minima; never beyond half.
        self.assertEqual(ss.mser_truncation([0.0, 1.0, 1.1, 0.9, 1.05, 0.95]), 1)
        self.assertLessEqual(ss.mser_truncation(np.arange(100.0)), 50)

    def test_a_heating_transient_is_skipped(self):
        # T rises linearly until strain 4 of 10 (like a dilute flow sheared from rest), then
        # fluctuates about its plateau; p follows it.
        rng = np.random.default_rng(5)
        n = 10000
        strain = np.arange(1, n + 1) * 1e-3
        temp = np.minimum(strain / 4, 1) + 0.05 * synthetic.ar1(0.9, n, rng)
        path = self.write("heat.h5", temp, 2 + 3 * temp)
        run = ss.read_run(path)
        start = ss.steady_start(run, 0.5)
        self.assertGreaterEqual(start, 3.7)
        self.assertLessEqual(start, 4.5)
        self.assertEqual(ss.steady_start(run, 6.0), 6.0)  # a later --from-strain wins
        ((value, err, _),) = [ss.steady_values(run, start)[0]["temperature"]]
        self.assertLess(abs(value - 1), 4 * err)
        self.assertGreater(1 - ss.steady_values(run, 0.5)[0]["temperature"][0], 10 * err)
        self.assertLess(ss.halves_z(run, start), ss.STATIONARY_SIGMAS)
        self.assertGreater(ss.halves_z(run, 0.5), ss.STATIONARY_SIGMAS)
        rows = ss.analyse([path], 0.5, detect_transient=True)
        self.assertEqual(rows[0][6][0], start)
        self.assertEqual(rows[0][5], int(np.sum(run["series"]["strain"] >= start)))
        self.assertEqual(ss.analyse([path], 0.5)[0][6][0], 0.5)

    def test_a_stationary_run_starts_early(self):
        for seed in range(5):
            rng = np.random.default_rng(seed)
            temp = 1 + 0.05 * synthetic.ar1(0.9, 5000, rng)
            run = ss.read_run(self.write(f"flat{seed}.h5", temp, 2 + 3 * temp))
            with self.subTest(seed=seed):
                # MSER may trim a fluctuation, but on average little.
                self.assertLessEqual(ss.steady_start(run, 0.5), 2.5)
                self.assertLess(ss.halves_z(run, ss.steady_start(run, 0.5)), ss.STATIONARY_SIGMAS)

    def test_a_run_that_never_settles_is_marked(self):
        rng = np.random.default_rng(6)
        n = 5000
        temp = np.arange(1, n + 1) / n + 0.02 * synthetic.ar1(0.9, n, rng)  # heats up to the end
        path = self.write("drift.h5", temp, 2 + 3 * temp)
        out = os.path.join(self.tmp.name, "drift_table.h5")
        res = subprocess.run(
            [sys.executable, SCRIPT, "--from-strain", "0.5", "--detect-transient", "-o", out, path],
            capture_output=True,
            text=True,
        )
        self.assertEqual(res.returncode, 0, res.stderr)
        table = ss.read_table(out)
        self.assertLessEqual(table["runs"]["steady_from"][0], 2.51)  # MSER stops at half the run
        self.assertGreater(table["runs"]["halves_z"][0], ss.STATIONARY_SIGMAS)
        self.assertEqual(table["runs"]["stationary"][0], 0)
        self.assertEqual(table["parameters"]["detect_transient"], 1)


class TableTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)
        rng = np.random.default_rng(4)
        self.runs = []
        for nu, e in ((0.8, 0.0), (0.7, 0.5)):
            p = 2 + 0.1 * synthetic.ar1(0.5, 1500, rng)
            path = os.path.join(self.tmp.name, f"shear_nu{nu:.3f}_e{e:.2f}.h5")
            synthetic.write_run(
                path, p - 1, np.ones(1500), 0.3 * p, np.full(1500, 0.2), packing_fraction=nu, restitution=e
            )
            self.runs.append(path)

    def run_cli(self, output, *runs):
        return subprocess.run(
            [sys.executable, SCRIPT, "--from-strain", "0.5", "-o", output, *runs], capture_output=True, text=True
        )

    def test_table_has_one_row_per_run_with_provenance(self):
        out = os.path.join(self.tmp.name, "table.h5")
        res = self.run_cli(out, *self.runs)
        self.assertEqual(res.returncode, 0, res.stderr)
        table = ss.read_table(out)
        self.assertEqual(list(table["runs"]["input"]), self.runs)
        for path, digest in zip(self.runs, table["runs"]["input_sha256"]):
            with open(path, "rb") as fh:
                self.assertEqual(digest, hashlib.sha256(fh.read()).hexdigest())
        np.testing.assert_allclose(table["runs"]["packing_fraction"], [0.8, 0.7])
        np.testing.assert_allclose(table["runs"]["restitution"], [0.0, 0.5])
        np.testing.assert_array_equal(table["runs"]["samples"], [1001, 1001])
        self.assertEqual(table["parameters"]["program"], "steady_state.py")
        self.assertEqual(table["parameters"]["from_strain"], 0.5)
        self.assertIn("Flyvbjerg-Petersen", table["parameters"]["error_method"])
        for name in ss.QUANTITIES:
            self.assertEqual(table["steady"][name].shape, (2,))
            self.assertTrue(np.all(np.isfinite(table["steady"][name + "_error"])))
        self.assertTrue(np.all(table["steady"]["pressure_scaled_error"] > 0))
        np.testing.assert_array_equal(table["steady"]["pressure_plateau"], [1, 1])
        np.testing.assert_allclose(table["steady"]["s_over_p"], 0.3)
        with h5py.File(out, "r") as f:
            self.assertEqual(f["steady/pressure_scaled"].attrs["unit"], b"1")
            self.assertEqual(f["steady/pressure"].attrs["unit"], b"M T-2")
            self.assertEqual(f["steady/pressure_error"].attrs["unit"], b"M T-2")
            self.assertEqual(f["steady/temperature"].attrs["unit"], b"L+2 T-2")
            self.assertEqual(f["runs/rate"].attrs["unit"], b"T-1")
            self.assertIn("meaning", f["steady/pressure_scaled_error"].attrs)
        np.testing.assert_array_equal(ss.select(table, friction=0.0), [1, 0])
        np.testing.assert_array_equal(ss.select(table, restitution=0.0), [0])
        self.assertEqual(glob.glob(os.path.join(self.tmp.name, ".*part*")), [])

    def test_bad_input_exits_2_and_writes_nothing(self):
        out = os.path.join(self.tmp.name, "bad.h5")
        missing = os.path.join(self.tmp.name, "missing.h5")
        for runs in ((missing,), (self.runs[0], missing)):
            res = self.run_cli(out, *runs)
            self.assertEqual(res.returncode, 2)
            self.assertIn("missing.h5", res.stderr)
            self.assertFalse(os.path.exists(out))
        with h5py.File(self.runs[1], "a") as f:
            del f["/observables/temperature"]
        res = self.run_cli(out, self.runs[1])
        self.assertEqual(res.returncode, 2)
        self.assertIn("temperature", res.stderr)
        self.assertEqual(glob.glob(os.path.join(self.tmp.name, ".*part*")), [])


if __name__ == "__main__":
    unittest.main()
