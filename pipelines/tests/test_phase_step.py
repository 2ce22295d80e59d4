"""phase_step.py: ν_bc(e) and the runs' dense/dilute class against the strain step, on
constructed inputs with known answers, and `make phase-step-files` end to end on the test size
(and its refusal of a grid with one step or without the size's own step)."""
import os
import tempfile
import unittest

import numpy as np

import study_make  # a sibling module: the step studies' make runner
from analysis import phase_step


def crossing(step, e, nu_bc, error, status="bracketed"):
    return {"step": step, "restitution": e, "friction": 0.0, "nu_bc": nu_bc, "nu_bc_error": error,
            "status": status, "nu_below": np.nan, "nu_above": np.nan, "nu_low": 0.7, "nu_high": 0.82}


def run(step, nu, e, ratio, measurable=True):
    return {"step": step, "packing_fraction": nu, "restitution": e, "friction": 0.0, "ratio": ratio,
            "ratio_error": 0.01, "measurable": measurable, "dense": measurable and ratio >= 1.25}


class ClassesTest(unittest.TestCase):
    def test_flat_crossover_is_converged(self):
        rows = [crossing(h, 0.5, 0.771, 0.003) for h in (1e-3, 2.5e-4, 1.25e-4, 6.25e-5)]
        (c,) = phase_step.classes(rows, 1e-3)
        self.assertEqual(c["class"], "converged")
        self.assertEqual(c["steps"], 4)

    def test_linear_drift_gives_its_limit(self):
        steps = np.array([2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4, 6.25e-5])
        nu = 0.80 - 20.0 * steps  # ν_bc rises towards 0.80 as the step shrinks
        rows = [crossing(h, 0.0, v, 1e-4) for h, v in zip(steps, nu)]
        (c,) = phase_step.classes(rows, 1e-3)
        self.assertEqual(c["class"], "converging")
        self.assertAlmostEqual(c["limit"], 0.80, delta=5e-4)

    def test_unbracketed_steps_are_left_out(self):
        rows = [crossing(1e-3, 0.9, 0.79, 0.01), crossing(2.5e-4, 0.9, np.nan, np.nan, "all_below")]
        self.assertEqual(phase_step.classes(rows, 1e-3), [])
        self.assertEqual(phase_step.crossing_text(rows[1]), "> 0.820")
        self.assertEqual(phase_step.crossing_text(crossing(1e-3, 0.9, np.nan, np.nan, "all_above")), "< 0.700")


class BadInputTest(unittest.TestCase):
    def test_one_table_is_refused(self):
        import contextlib
        import io

        with tempfile.TemporaryDirectory() as d:
            missing = os.path.join(d, "none.h5")
            err = io.StringIO()
            with contextlib.redirect_stderr(err):
                code = phase_step.main(["--default-step", "1e-3", "-o", os.path.join(d, "out.h5"), missing])
            self.assertEqual(code, 2)
            self.assertEqual(len(err.getvalue().strip().splitlines()), 1, err.getvalue())
            self.assertEqual(os.listdir(d), [])


class FlipsTest(unittest.TestCase):
    def test_flips_between_default_and_finest(self):
        runs = [
            run(1e-3, 0.80, 0.5, 1.40), run(2.5e-4, 0.80, 0.5, 1.30), run(1.25e-4, 0.80, 0.5, 1.20),
            run(1e-3, 0.76, 0.5, 1.10), run(1.25e-4, 0.76, 0.5, 1.05),
            run(1e-3, 0.82, 0.5, 1.60), run(1.25e-4, 0.82, 0.5, 1.50),
            # Not measurable at the finest step: not compared.
            run(1e-3, 0.79, 0.5, 1.30), run(1.25e-4, 0.79, 0.5, 1.10, measurable=False),
        ]
        finest, common, changed = phase_step.flips(runs, 1e-3)
        self.assertEqual(finest, 1.25e-4)
        self.assertEqual(len(common), 3)
        self.assertEqual(changed, [(0.80, 0.5, 0.0)])


GRID = """CONV_POINTS       := 0.700:0.50:0.00
CONV_REFERENCE    := 0.500:0.92:0.00
CONV_STEPS        := 2e-3 1e-3
CONV_DEFAULT_STEP := 1e-3
PHASE_STEPS       := {steps}
PHASE_NU          := 0.700
"""


@unittest.skipUnless(study_make.HAVE_PROGRAMS, study_make.SKIP_REASON)
class PhaseStepMakeTest(unittest.TestCase):
    """make phase-step-files on the test size (64 grains) at two steps."""

    def make(self, d, steps, *extra):
        # The reference at ν = 0.7: 64 dilute elastic grains may have no contact in any frame.
        return study_make.run(d, GRID.format(steps=steps), ("CONVERGENCE", "PHASE_GRID"),
                              ("gf-pack", "gf-shear", "gf-correlate"), "phase-step-files", "SIZE=test",
                              "CH5_REFERENCE_NU=0.700", *extra)

    def test_two_steps(self):
        import h5py

        with tempfile.TemporaryDirectory() as d:
            res = self.make(d, "1e-3 5e-4")
            self.assertEqual(res.returncode, 0, res.stdout + res.stderr)
            # Each step's runs at its own step, frames at the same strain spacing.
            for h, every in (("1e-3", 10), ("5e-4", 20)):
                with h5py.File(f"{d}/runs/ch5_dt{h}/shear_nu0.700_e0.00_mu0.00_r1e-02_s1.h5", "r") as f:
                    a = f["parameters"].attrs
                    self.assertAlmostEqual(float(a["rate"]) * float(a["dt"]), float(h), delta=1e-12)
                    self.assertEqual(int(a["frame-every"]), every)
            self.assertFalse(os.path.exists(f"{d}/runs/ch5_dt1e-3/shear_nu0.700_e0.00_mu0.40_r1e-02_s1.h5"))
            with h5py.File(f"{d}/runs/phase_step.h5", "r") as f:
                # One row per (step, run) of the sweep but the reference: ν = 0.7, e = 0 at each step.
                self.assertEqual(sorted(np.round(f["runs_by_step/step"][()], 12)), [5e-4, 1e-3])
                self.assertEqual(sorted(set(f["runs_by_step/packing_fraction"][()])), [0.7])
                # Crossings per (step, e) where the step's table has a sweep; μ = 0 only.
                self.assertTrue(set(np.round(f["crossover/step"][()], 12)) <= {5e-4, 1e-3})
                self.assertEqual(sorted(set(f["crossover/friction"][()])), [0.0])
                self.assertEqual(float(f["parameters"].attrs["default_step"]), 1e-3)
            with open(f"{d}/runs/phase_step.md") as fh:
                md = fh.read()
            self.assertIn("| e | μ | γ̇dt = 0.001 | γ̇dt = 0.0005 | class |", md)
            self.assertIn("Runs whose class differs between γ̇dt = 0.001 and 0.0005", md)
            with open(f"{d}/figures/fig5_10_step.png", "rb") as fh:
                self.assertEqual(fh.read(8), b"\x89PNG\r\n\x1a\n")
            # A second make remakes nothing.
            before = os.stat(f"{d}/runs/phase_step.h5").st_mtime_ns
            again = self.make(d, "1e-3 5e-4")
            self.assertEqual(again.returncode, 0, again.stdout + again.stderr)
            self.assertNotIn("gf-shear", again.stdout)
            self.assertEqual(os.stat(f"{d}/runs/phase_step.h5").st_mtime_ns, before)

    def test_one_step_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            study_make.assert_refused(self, self.make(d, "1e-3"), d, "PHASE_STEPS needs at least two strain steps")

    def test_steps_without_the_size_step_are_refused(self):
        with tempfile.TemporaryDirectory() as d:
            study_make.assert_refused(self, self.make(d, "2e-3 5e-4"), d, "SHEAR_STRAIN_STEP")


if __name__ == "__main__":
    unittest.main()
