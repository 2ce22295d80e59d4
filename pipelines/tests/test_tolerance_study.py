"""tolerance_study.py: the verdict on constructed inputs (one observable that moves, one that does
not), its refusals; the friction-tolerance make target end to end on a tiny grid (the summary's
shape and units, nothing left to do on a second make) and its refusal of a grid with one tolerance."""
import csv
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import study_make  # a sibling module: the step studies' make runner
import synthetic
from analysis import sliding_share, tolerance_study

ROOT = study_make.ROOT


class VerdictTest(unittest.TestCase):
    def rows(self, p_loose, z_loose):
        """Two seeds at one ν, tolerances 1e-10 (default), 1e-9, 1e-8; p and z at the loosest as given."""
        rows = {}
        for seed in (1, 2):
            rows[(0.76, seed, 1e-10)] = {"p": (10.0, 0.1), "z": (1.0, 0.03)}
            rows[(0.76, seed, 1e-9)] = {"p": (10.05, 0.1), "z": (1.01, 0.03)}
            rows[(0.76, seed, 1e-8)] = {"p": (p_loose if seed == 2 else 10.0, 0.1), "z": (z_loose, 0.03)}
        return rows

    def test_one_moves_one_does_not(self):
        # p at 1e-8, seed 2: 0.5 from the default over √2·0.1 = 3.5 combined errors; z within 1.
        series, verdicts = tolerance_study.compare(self.rows(10.5, 1.03), 1e-10, 2.0)
        self.assertEqual(verdicts["p"]["verdict"], "moves")
        self.assertAlmostEqual(verdicts["p"]["max_sigmas"], 0.5 / math.hypot(0.1, 0.1))
        self.assertEqual((verdicts["p"]["worst_seed"], verdicts["p"]["worst_tolerance"]), (2, 1e-8))
        self.assertEqual(verdicts["z"]["verdict"], "does not move")
        self.assertAlmostEqual(verdicts["z"]["max_sigmas"], 0.03 / math.hypot(0.03, 0.03))
        # One row per (ν, seed, observable, tolerance); the default's difference is 0.
        self.assertEqual(len(series), 1 * 2 * 2 * 3)
        for r in series:
            if r["tolerance"] == 1e-10:
                self.assertEqual((r["difference"], r["sigmas"]), (0.0, 0.0))
            self.assertEqual(r["verdict"], verdicts[r["observable"]]["verdict"])

    def test_just_inside_the_bound_does_not_move(self):
        _, verdicts = tolerance_study.compare(self.rows(10.0 + 1.99 * math.hypot(0.1, 0.1), 1.0), 1e-10, 2.0)
        self.assertEqual(verdicts["p"]["verdict"], "does not move")
        _, verdicts = tolerance_study.compare(self.rows(10.0 + 2.01 * math.hypot(0.1, 0.1), 1.0), 1e-10, 2.0)
        self.assertEqual(verdicts["p"]["verdict"], "moves")

    def test_a_difference_without_error_is_undecided(self):
        rows = self.rows(10.0, 1.0)
        rows[(0.76, 1, 1e-8)]["z"] = (1.001, math.nan)
        _, verdicts = tolerance_study.compare(rows, 1e-10, 2.0)
        self.assertEqual(verdicts["z"]["verdict"], "undecided")

    def test_a_point_without_the_default_is_refused(self):
        rows = self.rows(10.0, 1.0)
        del rows[(0.76, 2, 1e-10)]
        with self.assertRaisesRegex(ValueError, "seed 2: no run at the default tolerance"):
            tolerance_study.compare(rows, 1e-10, 2.0)

    def test_bad_input_exits_2_with_one_line_and_writes_nothing(self):
        with tempfile.TemporaryDirectory() as d:
            env = dict(os.environ, PYTHONPATH=f"{ROOT}/python:{ROOT}/pipelines")
            for args in ([f"{d}/missing.h5"], ["--sigmas", "0", f"{d}/missing.h5"]):
                res = subprocess.run([sys.executable, f"{ROOT}/pipelines/analysis/tolerance_study.py", "-o",
                                      f"{d}/out.h5", "--csv", f"{d}/out.csv", *args],
                                     capture_output=True, text=True, env=env)
                self.assertEqual(res.returncode, 2, res.stderr)
                self.assertEqual(len(res.stderr.strip().splitlines()), 1, res.stderr)
                self.assertEqual(os.listdir(d), [])


class SlidingShareTest(unittest.TestCase):
    """sliding_share.analyse on a constructed μ = 0.4 trajectory: per frame 9 force-bearing contacts,
    3 on the Coulomb limit (one of them F_t = −μF_n), one at (1 − 10⁻³)μF_n (sticking), one F_n = 0;
    the frames before the window hold only sliding contacts, and must not count."""

    def write(self, path):
        import h5py

        synthetic.write_run(path, np.full(4000, 1.0), np.full(4000, 0.1), np.full(4000, 0.3), np.full(4000, 1.0),
                            friction=0.4, frame_every=50)
        fn = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 0.0])
        ft = 0.4 * fn * np.array([1, -1, 1, 1 - 1e-3, 0.5, 0.1, 0, -0.3, 0.9, 0])
        with h5py.File(path, "a") as f:
            steps = f["particles/grains/position/step"][()]
            normal, tangential = [], []
            for step in steps:
                before = step <= 1000  # steps 1..1000 come before the window below (strain >= 1.0005: rows from 1001)
                normal.append(fn)
                tangential.append(0.4 * fn if before else ft)
            c = f.create_group("contacts")
            c["frame_offset"] = np.arange(len(steps) + 1, dtype=np.int64) * len(fn)
            c["normal_force"] = np.concatenate(normal)
            c["tangential_force"] = np.concatenate(tangential)
        return len(steps[steps > 1000])

    def test_share_over_the_window(self):
        with tempfile.TemporaryDirectory() as d:
            frames = self.write(f"{d}/run.h5")
            share, error, sliding, bearing, counted, mu = sliding_share.analyse(f"{d}/run.h5", 1.0005, 1e-6)
            self.assertEqual((sliding, bearing, counted, mu), (3.0, 9.0, frames, 0.4))
            self.assertAlmostEqual(share, 1 / 3, places=15)
            self.assertEqual(error, 0.0)
            # A margin of 10⁻² counts the contact at (1 − 10⁻³)μF_n too.
            self.assertAlmostEqual(sliding_share.analyse(f"{d}/run.h5", 1.0005, 1e-2)[0], 4 / 9, places=15)

    def test_frictionless_run_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            synthetic.write_run(f"{d}/run.h5", *(np.full(4000, 1.0),) * 4, friction=0.0)
            with self.assertRaisesRegex(ValueError, "not a gf-shear trajectory with contacts|no Coulomb limit"):
                sliding_share.analyse(f"{d}/run.h5", 1.0, 1e-6)


GRID = """FT_GRAINS            := 64
FT_NU                := 0.760
FT_RESTITUTION       := 0.00
FT_FRICTION          := 0.40
FT_SEEDS             := 1 2
FT_TOLERANCES        := {tolerances}
FT_DEFAULT_TOLERANCE := 1e-10
FT_STEP              := 1e-3
FT_STRAIN            := 0.3
FT_RATE              := 1
FT_FROM_STRAIN       := 0.05
FT_OBSERVE_STRAIN    := 2e-3
FT_FRAME_STRAIN      := 2e-3
FT_SLIDING_MARGIN    := 1e-6
FT_SIGMAS            := 2
"""


@unittest.skipUnless(study_make.HAVE_PROGRAMS, study_make.SKIP_REASON)
class FrictionToleranceMakeTest(unittest.TestCase):
    """make friction-tolerance-files on a 64-grain grid: one ν, two seeds, two tolerances."""

    def make(self, d, tolerances, *extra):
        return study_make.run(d, GRID.format(tolerances=tolerances), ("FRICTION_TOLERANCE",),
                              ("gf-pack", "gf-shear", "gf-network"), "friction-tolerance-files",
                              f"FT_RUNS={d}/runs", *extra)

    def test_tiny_study(self):
        import h5py

        from granflow import units
        from granflow.hdf5 import text

        with tempfile.TemporaryDirectory() as d:
            res = self.make(d, "1e-10 1e-8")
            self.assertEqual(res.returncode, 0, res.stdout + res.stderr)
            with h5py.File(f"{d}/runs/friction_tolerance.h5", "r") as f:
                self.assertEqual(units.table_problems(f), [])
                s = {k: f["series"][k][()] for k in f["series"]}
                obs = [o.decode() if isinstance(o, bytes) else o for o in s["observable"]]
                # One ν × two seeds × five observables × two tolerances.
                self.assertEqual(len(obs), 1 * 2 * 5 * 2)
                self.assertEqual(set(obs), {"p", "s_over_p", "T", "z", "sliding"})
                self.assertEqual(sorted(set(s["tolerance"])), [1e-10, 1e-8])
                self.assertEqual(sorted(set(s["seed"])), [1, 2])
                self.assertEqual(text(f["series/tolerance"].attrs["unit"]), "L")
                self.assertEqual(text(f["series/value"].attrs["unit_column"]), "unit")
                at_default = s["tolerance"] == 1e-10
                self.assertTrue(np.all(s["difference"][at_default] == 0))
                share = s["value"][np.array(obs) == "sliding"]
                self.assertTrue(np.all((share >= 0) & (share <= 1)), share)
                verdicts = [v.decode() if isinstance(v, bytes) else v for v in f["verdicts/verdict"][()]]
                self.assertEqual(len(verdicts), 5)
                self.assertTrue(set(verdicts) <= {"moves", "does not move", "undecided"})
                self.assertEqual(float(f["parameters"].attrs["friction"]), 0.4)
            with open(f"{d}/runs/friction_tolerance.csv", newline="") as fh:
                lines = [line for line in fh if not line.startswith("#")]
            rows = list(csv.DictReader(lines))
            self.assertEqual(len(rows), 20)
            self.assertEqual(set(r["tolerance"] for r in rows), {"1e-10", "1e-08"})
            # Nothing left to do.
            q = self.make(d, "1e-10 1e-8", "-q")
            self.assertEqual(q.returncode, 0, q.stdout + q.stderr)

    def test_grid_with_one_tolerance_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            study_make.assert_refused(self, self.make(d, "1e-10"), d, "FT_TOLERANCES needs at least two tolerances")

    def test_default_outside_the_grid_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            study_make.assert_refused(self, self.make(d, "1e-9 1e-8"), d, "FT_DEFAULT_TOLERANCE")


if __name__ == "__main__":
    unittest.main()
