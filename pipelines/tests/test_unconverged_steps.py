"""unconverged_steps.py: exact answers on a constructed trajectory (a spike at one capped step, none
at another, two adjacent capped steps, one before the window), its refusals, and the count on a
gf-shear run whose steps are capped at one sweep, against the run's /run summary."""
import os
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

import study_make
import synthetic
from analysis import unconverged_steps

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "analysis", "unconverged_steps.py")
TOLERANCE = 1e-10


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


def constructed(path, rows=3000, capped=None, every=1):
    """p = 10, s = 1, T = 1 at every step but p = 20 at step 2000; the steps of `capped` (step:
    residual) at or above the tolerance, the others 1e-12; rows every `every` steps."""
    capped = {500: 3e-10, 1500: 5e-10, 2000: 2e-9, 2500: 1e-10, 2501: 1e-8} if capped is None else capped
    ps = np.full(rows, 10.0)
    ps[2000 - 1] = 20.0
    synthetic.write_run(path, ps, np.zeros(rows), np.ones(rows), np.ones(rows))
    with h5py.File(path, "r+") as f:
        f["parameters"].attrs["tolerance"] = TOLERANCE
        residual = f["observables/solver_residual/value"]
        for step, r in capped.items():
            residual[step - 1] = r
        if every != 1:
            for name in f["observables"]:
                f[f"observables/{name}/step"][...] *= every
    return path


class ConstructedTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.path = constructed(os.path.join(self.tmp.name, "run.h5"))

    def tearDown(self):
        self.tmp.cleanup()

    def test_known_answers(self):
        rows = {r["observable"]: r for r in unconverged_steps.analyse(self.path, 0.9995)}
        p, sp, t = rows["p"], rows["s/p"], rows["T"]
        # Steps 1500, 2000, 2500, 2501 in the window (from step 1000); 1500 and 2000 isolated.
        self.assertEqual((p["capped"], p["isolated"]), (4, 2))
        # Residuals 5, 20, 1, 100 tolerances.
        self.assertAlmostEqual(p["residual_median"], 12.5)
        self.assertAlmostEqual(p["residual_max"], 100.0)
        # Spikes of p at the isolated steps: 1 (1500) and 2 (2000); their quantiles 1.1, 1.5, 1.9.
        for q, want in ((10, 1.1), (50, 1.5), (90, 1.9)):
            self.assertAlmostEqual(p[f"spike_capped_p{q}"], want)
            self.assertAlmostEqual(sp[f"spike_capped_p{q}"], 0.5 + q / 200)  # s/p: 1 and 1/2
            self.assertAlmostEqual(t[f"spike_capped_p{q}"], 1.0)
            for ref in ("nearby", "ordinary"):
                self.assertAlmostEqual(p[f"spike_{ref}_p{q}"], 1.0)
        # p = 20 at one of four capped steps, above every converged step: mean percentile 1/4.
        self.assertAlmostEqual(p["percentile"], 0.25)
        # Window of 2001 rows, sum 20020; without the 4 capped steps, 10.
        self.assertAlmostEqual(p["drop_effect"], -10 / 20020)
        self.assertAlmostEqual(t["drop_effect"], 0.0)
        # The spike of 10 at step 2000 over a window sum of 20020; s/p: -0.05 over 2000·0.1 + 0.05.
        self.assertAlmostEqual(p["spike_effect"], 10 / 20020)
        self.assertAlmostEqual(sp["spike_effect"], -0.05 / 200.05)
        self.assertAlmostEqual(t["spike_effect"], 0.0)

    def test_the_programs_count_first(self):
        """With /observables/unconverged_steps (written by gf-shear) the capped steps are the
        rows it counts, not the residuals: here it leaves out step 1500."""
        with h5py.File(self.path, "r+") as f:
            steps = f["observables/pressure/step"][()]
            count = np.isin(steps, [500, 2000, 2500, 2501]).astype(float)
            g = f["observables"].create_group("unconverged_steps")
            g["step"], g["time"], g["value"] = steps, f["observables/pressure/time"][()], count
        p = unconverged_steps.analyse(self.path, 0.9995)[0]
        self.assertEqual((p["capped"], p["isolated"]), (3, 1))
        self.assertAlmostEqual(p["residual_median"], 20.0)

    def test_csv_and_table(self):
        out = os.path.join(self.tmp.name, "u.csv")
        res = run(self.path, "--from-strain", "0.9995", "--csv", out)
        self.assertEqual(res.returncode, 0, res.stderr)
        with open(out) as f:
            lines = f.read().splitlines()
        self.assertTrue(lines[0].startswith("# unconverged_steps.py "))
        self.assertEqual(lines[1:], res.stdout.splitlines())
        self.assertEqual(lines[1].split(",")[:4], ["run", "observable", "capped", "isolated"])
        self.assertEqual(len(lines), 2 + 3)

    def test_bad_input(self):
        d = self.tmp.name
        sparse = constructed(os.path.join(d, "sparse.h5"), every=2)
        clean = constructed(os.path.join(d, "clean.h5"), capped={})
        untold = constructed(os.path.join(d, "untold.h5"))
        with h5py.File(untold, "r+") as f:
            del f["parameters"].attrs["tolerance"]
        packing = os.path.join(d, "pack.h5")
        synthetic.write_packing(packing)
        cases = {
            "missing": [os.path.join(d, "nope.h5")],
            "not one row per step": [sparse],
            "no capped step": [clean],
            "no tolerance": [untold],
            "not gf-shear": [packing],
            "window too short": [self.path, "--from-strain", "2.95"],
            "bad strain": [self.path, "--from-strain", "nan"],
        }
        for what, args in cases.items():
            out = os.path.join(d, "out.csv")
            res = run(*args, "--csv", out)
            self.assertEqual(res.returncode, 2, what)
            self.assertEqual(len(res.stderr.splitlines()), 1, res.stderr)
            self.assertTrue(res.stderr.startswith("unconverged_steps.py: error: "), res.stderr)
            self.assertFalse(os.path.exists(out), what)


@unittest.skipUnless(study_make.HAVE_PROGRAMS, study_make.SKIP_REASON)
class GfShearTest(unittest.TestCase):
    def test_count_is_the_runs(self):
        """One sweep per step leaves some steps at the cap; the script finds exactly /run's count."""
        binary = os.environ["GRANFLOW_BIN"]
        with tempfile.TemporaryDirectory() as d:
            pack, out = os.path.join(d, "pack.h5"), os.path.join(d, "run.h5")
            subprocess.run([os.path.join(binary, "gf-pack"), "--grains", "100", "--packing-fraction", "0.7", "--seed",
                            "4", "-o", pack, "-q"], check=True)
            subprocess.run([os.path.join(binary, "gf-shear"), "-i", pack, "-o", out, "--rate", "0.01", "--steps", "210",
                            "--max-iterations", "1", "--max-unconverged", "1", "-q"], check=True, capture_output=True)
            with h5py.File(out, "r") as f:
                count = int(f["run"].attrs["unconverged_steps"])
                largest = float(f["run"].attrs["max_residual"])
                tolerance = float(f["parameters"].attrs["tolerance"])
            self.assertGreater(count, 20)
            rows = unconverged_steps.analyse(out, 0.0)
            self.assertEqual(rows[0]["capped"], count)
            self.assertAlmostEqual(rows[0]["residual_max"], largest / tolerance)


if __name__ == "__main__":
    unittest.main()
