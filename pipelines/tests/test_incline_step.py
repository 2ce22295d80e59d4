"""incline_step.py: the incline's observables against its time step, `make incline-step-files`
end to end on the test size (and its refusal of a grid with one step or without the size's)."""
import os
import tempfile
import unittest

import numpy as np

import study_make  # a sibling module: the step studies' make runner
from analysis import incline_step

GRID = """INCLINE_STEPS       := {steps}
INCLINE_STEP_ANGLES := 20
"""


class BadInputTest(unittest.TestCase):
    def test_missing_table_is_refused(self):
        import contextlib
        import io

        with tempfile.TemporaryDirectory() as d:
            err = io.StringIO()
            with contextlib.redirect_stderr(err):
                code = incline_step.main(["--default-step", "5e-3", "-o", os.path.join(d, "out.h5"),
                                          os.path.join(d, "none.h5")])
            self.assertEqual(code, 2)
            self.assertEqual(len(err.getvalue().strip().splitlines()), 1, err.getvalue())
            self.assertEqual(os.listdir(d), [])


@unittest.skipUnless(study_make.HAVE_PROGRAMS, study_make.SKIP_REASON)
class InclineStepMakeTest(unittest.TestCase):
    """make incline-step-files on the test size (a layer of about a hundred grains) at two steps."""

    def make(self, d, steps, *extra):
        return study_make.run(d, GRID.format(steps=steps), ("INCLINE_STEP_GRID",), ("gf-pack", "gf-incline"),
                              "incline-step-files", "SIZE=test", *extra)

    def test_two_steps(self):
        import h5py

        with tempfile.TemporaryDirectory() as d:
            res = self.make(d, "1e-2 5e-3")
            self.assertEqual(res.returncode, 0, res.stdout + res.stderr)
            # Each step's run at its own step, profile blocks at the same spacing in time.
            for h, block in (("1e-2", 100), ("5e-3", 200)):
                with h5py.File(f"{d}/runs/incline_dt{h}/incline_th20_e0.50_mu0.00_s1.h5", "r") as f:
                    a = f["parameters"].attrs
                    self.assertAlmostEqual(float(a["dt"]) / float(a["tau"]), float(h), delta=1e-12)
                    self.assertEqual(int(a["profile-block"]), block)
            self.assertEqual([p for p in os.listdir(f"{d}/runs/incline_dt5e-3") if "mu0.40" in p], [])
            with h5py.File(f"{d}/runs/incline_step.h5", "r") as f:
                steps = f["series/step"][()]
                self.assertEqual(sorted(set(np.round(steps, 12))), [5e-3, 1e-2])
                obs = {o.decode() if isinstance(o, bytes) else o for o in f["series/observable"][()]}
                self.assertTrue({"flow_rate", "velocity_exponent", "s_over_p", "nu"} <= obs)
                classes = {c.decode() if isinstance(c, bytes) else c for c in f["classes/class"][()]}
                self.assertTrue(classes <= {"converged", "converging", "regularisation-dependent", "unsettled"})
                self.assertEqual(float(f["parameters"].attrs["default_step"]), 5e-3)
            with open(f"{d}/runs/incline_step.md") as fh:
                md = fh.read()
            self.assertIn("### θ = 20°, μ = 0", md)
            self.assertIn("dt = 0.005 τ (default)", md)
            self.assertIn("| flow rate V̄/√(g⟨R⟩) |", md)
            before = os.stat(f"{d}/runs/incline_step.h5").st_mtime_ns
            again = self.make(d, "1e-2 5e-3")
            self.assertEqual(again.returncode, 0, again.stdout + again.stderr)
            self.assertNotIn("gf-incline", again.stdout)
            self.assertEqual(os.stat(f"{d}/runs/incline_step.h5").st_mtime_ns, before)

    def test_one_step_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            study_make.assert_refused(self, self.make(d, "5e-3"), d, "INCLINE_STEPS needs at least two time steps")

    def test_steps_without_the_size_step_are_refused(self):
        with tempfile.TemporaryDirectory() as d:
            study_make.assert_refused(self, self.make(d, "1e-2 2.5e-3"), d, "INCLINE_TIME_STEP")


if __name__ == "__main__":
    unittest.main()
