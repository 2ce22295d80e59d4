"""Tests of jamming_point.py: the fit of q = A (ν_c − ν)^−β on constructed data whose ν_c, β and
A are known (exact, and with noise of known size), its intervals' coverage, its refusals, and
the program end to end on a table in steady_state.py's layout."""
import math
import os
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

from analysis import jamming_point as jp
from report import ch5

PIPELINES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
# The package granflow's source directory (python/ beside pipelines/).
PACKAGE = os.path.join(PIPELINES, "..", "python")
NU = np.array([0.70, 0.73, 0.75, 0.76, 0.77, 0.78, 0.785, 0.79, 0.795])


def law(nu, nu_c=0.806, beta=1.9, amplitude=0.0024):
    return amplitude * (nu_c - nu) ** (-beta)


class FitTest(unittest.TestCase):
    def test_exact_data_recovered(self):
        q = law(NU)
        fit = jp.fit_divergence(NU, q, 0.03 * q)
        self.assertAlmostEqual(fit["nu_c"], 0.806, places=7)
        self.assertAlmostEqual(fit["exponent"], 1.9, places=5)
        self.assertAlmostEqual(fit["amplitude"] / 0.0024, 1.0, places=4)
        self.assertLess(fit["chi2"], 1e-8)
        self.assertEqual((fit["points"], fit["dof"]), (9, 6))
        self.assertTrue(math.isnan(fit["exponent_fixed"]))
        self.assertLess(fit["nu_c_low"], 0.806)
        self.assertGreater(fit["nu_c_high"], 0.806)
        self.assertLess(fit["nu_c_high"] - fit["nu_c_low"], 0.01)

    def test_fixed_exponent_readings(self):
        q = law(NU)
        right = jp.fit_divergence(NU, q, 0.03 * q, exponent=1.9)
        self.assertAlmostEqual(right["nu_c"], 0.806, places=7)
        self.assertEqual(right["dof"], 7)
        self.assertEqual(right["exponent"], 1.9)
        # A larger β puts the divergence further away (the same growth needs a larger distance).
        wrong = jp.fit_divergence(NU, q, 0.03 * q, exponent=2.5)
        self.assertGreater(wrong["nu_c"], 0.806 + 1e-3)
        self.assertGreater(wrong["chi2"], 1.0)

    def test_interval_coverage_with_noise(self):
        # Lognormal noise of the stated size: the profile interval (Δχ² = 1, or χ²/dof when
        # larger) should hold the true ν_c about as often as a 1σ interval does.
        rng = np.random.default_rng(7)
        hits, trials = 0, 120
        for _ in range(trials):
            q = law(NU) * np.exp(0.05 * rng.normal(size=NU.size))
            fit = jp.fit_divergence(NU, q, 0.05 * q)
            hits += fit["nu_c_low"] <= 0.806 <= fit["nu_c_high"]
        self.assertGreater(hits / trials, 0.55)
        self.assertLess(hits / trials, 0.82)

    def test_no_divergence_seen(self):
        rng = np.random.default_rng(3)
        q = 5.0 * np.exp(0.01 * rng.normal(size=NU.size))
        fit = jp.fit_divergence(NU, q, 0.01 * q)
        self.assertEqual(fit["nu_c"], math.inf)
        self.assertEqual(fit["nu_c_high"], math.inf)

    def test_refusals(self):
        q = law(NU)
        with self.assertRaisesRegex(ValueError, "cannot fit 3 parameters"):
            jp.fit_divergence(NU[:3], q[:3], q[:3] * 0.01)
        jp.fit_divergence(NU[:3], q[:3], q[:3] * 0.01, exponent=2.0)  # 2 parameters, 1 dof: fine
        with self.assertRaisesRegex(ValueError, "finite and > 0"):
            jp.fit_divergence(NU, q, 0.0 * q)
        bad = q.copy()
        bad[2] = -1.0
        with self.assertRaisesRegex(ValueError, "finite and > 0"):
            jp.fit_divergence(NU, bad, 0.01 * q)


def write_table(path, rows):
    """A table in steady_state.py's layout: rows of (input, ν, μ, e, p, s)."""
    with h5py.File(path, "w") as f:
        f.create_group("parameters")
        f.create_group("diagnostics")
        runs, steady = f.create_group("runs"), f.create_group("steady")
        runs["input"] = np.array([r[0] for r in rows], dtype=object).astype(h5py.string_dtype())
        for k, name in enumerate(("packing_fraction", "friction", "restitution"), start=1):
            runs[name] = np.array([r[k] for r in rows])
        for k, name in ((4, "pressure_scaled"), (5, "shear_stress_scaled")):
            steady[name] = np.array([r[k] for r in rows])
            steady[name + "_error"] = 0.02 * np.array([r[k] for r in rows])


class ProgramTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)

    def run_program(self, *args):
        env = dict(os.environ, PYTHONPATH=os.pathsep.join((PACKAGE, PIPELINES)))
        return subprocess.run([sys.executable, os.path.join(PIPELINES, "analysis", "jamming_point.py"), *args],
                              env=env, capture_output=True, text=True)

    def test_groups_duplicates_and_filter(self):
        frictionless = [(f"a{nu}", nu, 0.0, 0.0, law(nu, 0.84, 2.2), 0.1 * law(nu, 0.84, 2.2)) for nu in NU]
        frictional = [(f"b{nu}", nu, 0.4, 0.0, law(nu), 0.4 * law(nu)) for nu in NU]
        first, second = (os.path.join(self.tmp.name, n) for n in ("t1.h5", "t2.h5"))
        write_table(first, frictionless + frictional[:5])
        # The second table repeats two runs of the first (counted once) and adds the rest.
        write_table(second, frictional[3:])
        out = os.path.join(self.tmp.name, "fit.h5")
        done = self.run_program("-o", out, first, second)
        self.assertEqual(done.returncode, 0, done.stderr)
        with h5py.File(out, "r") as f:
            fits = f["fits"]
            self.assertEqual(len(fits["nu_c"]), 8)  # 2 groups x 2 quantities x (free, β = 2)
            quantity = [q.decode() for q in fits["quantity"][...]]
            for i in range(8):
                expected = 0.84 if fits["friction"][i] == 0.0 else 0.806
                self.assertEqual(fits["points"][i], 9)
                if math.isnan(fits["exponent_fixed"][i]):
                    self.assertAlmostEqual(fits["nu_c"][i], expected, places=6, msg=quantity[i])
            self.assertEqual(f["parameters"].attrs["program"], "jamming_point.py")
            self.assertEqual(len(f["runs/input"]), 2)
        out2 = os.path.join(self.tmp.name, "fit2.h5")
        done = self.run_program("--friction", "0.4", "--exponent", "1.9", "--exponent", "2.5", "-o", out2, first, second)
        self.assertEqual(done.returncode, 0, done.stderr)
        with h5py.File(out2, "r") as f:
            self.assertEqual(set(f["fits/friction"][...]), {0.4})
            self.assertEqual(len(f["fits/nu_c"]), 6)
            np.testing.assert_array_equal(f["parameters"].attrs["exponents"], [1.9, 2.5])
        # The report's section: one row per group, the known ν_c of each quantity's free fit.
        text = "\n".join(ch5.jamming_section(out))
        self.assertIn("(thesis l. 568)", text)
        self.assertRegex(text, r"\| 0 \| 0 \| 9 \| 0\.795 \| 0\.8400 \[0\.8\d+, 0\.8\d+\] \| 2\.20 \|")
        self.assertRegex(text, r"\| 0\.4 \| 0 \| 9 \| 0\.795 \| 0\.8060 \[.*\| 0\.8060 \[[^|]*\| 1\.90 \|")

    def test_small_group_skipped(self):
        few = os.path.join(self.tmp.name, "few.h5")
        rows = [(f"c{nu}", nu, 0.4, 0.0, law(nu), 0.05 * law(nu)) for nu in NU[:3]]
        rows += [(f"d{nu}", nu, 0.0, 0.0, law(nu, 0.84), 0.05 * law(nu, 0.84)) for nu in NU[:6]]
        write_table(few, rows)
        out = os.path.join(self.tmp.name, "fit.h5")
        done = self.run_program("-o", out, few)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("μ = 0.4, e = 0: not fitted, 3 runs", done.stderr)
        with h5py.File(out, "r") as f:
            self.assertEqual(set(f["fits/friction"][...]), {0.0})
            self.assertEqual(list(f["skipped/friction"][...]), [0.4])
            self.assertEqual(list(f["skipped/points"][...]), [3])
        self.assertIn("Not fitted (fewer than 4 runs at ν ≥ 0.7): μ = 0.4, e = 0 (3).",
                      "\n".join(ch5.jamming_section(out)))
        # Only the small group selected: a table with no fit, the group listed.
        done = self.run_program("--friction", "0.4", "-o", out, few)
        self.assertEqual(done.returncode, 0, done.stderr)
        with h5py.File(out, "r") as f:
            self.assertEqual(len(f["fits/nu_c"]), 0)
            self.assertEqual(list(f["skipped/points"][...]), [3])
        self.assertNotIn("| μ | e |", "\n".join(ch5.jamming_section(out)))

    def test_bad_input_writes_nothing(self):
        out = os.path.join(self.tmp.name, "fit.h5")
        table = os.path.join(self.tmp.name, "table.h5")
        write_table(table, [(f"c{nu}", nu, 0.4, 0.0, law(nu), law(nu)) for nu in NU])
        not_a_table = os.path.join(self.tmp.name, "other.h5")
        with h5py.File(not_a_table, "w") as f:
            f["x"] = 1
        done = self.run_program("-o", out, not_a_table)
        self.assertEqual(done.returncode, 2)
        self.assertIn("not a steady_state.py table", done.stderr)
        done = self.run_program("--friction", "0.9", "-o", out, table)
        self.assertEqual(done.returncode, 2)
        self.assertIn("no rows match", done.stderr)
        done = self.run_program("--exponent", "-1", "-o", out, table)
        self.assertEqual(done.returncode, 2)
        self.assertIn("--exponent must be > 0", done.stderr)
        self.assertEqual([n for n in os.listdir(self.tmp.name) if n.startswith("fit") or n.startswith(".fit")], [])

if __name__ == "__main__":
    unittest.main()
