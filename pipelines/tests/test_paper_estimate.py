"""bench/paper_estimate.py (docs/performance.md's estimate of the paper size's frictional CPU
hours) on costs whose answers are known by hand: a constant cost gives the grids' total strain
times it, the log-linear interpolation halfway between two costs gives their geometric mean,
and bad input is refused with exit code 2."""
import importlib.util
import os
import subprocess
import sys
import unittest

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "bench", "paper_estimate.py")
_spec = importlib.util.spec_from_file_location("paper_estimate", SCRIPT)
paper_estimate = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(paper_estimate)


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


class PaperEstimate(unittest.TestCase):
    def test_grids_total_strain(self):
        # Fig. 5.4: 2 frictions x (8 runs of 80 + 7 of 20); Fig. 4.10: 1 run of 80 + 6 of 20.
        runs = paper_estimate.shear_runs()
        self.assertEqual(len(runs), 37)
        self.assertEqual(sum(strain for _, strain in runs), 2 * (8 * 80 + 7 * 20) + 80 + 6 * 20)

    def test_interpolation_is_log_linear_and_flat_outside(self):
        costs = {0.70: 1.0, 0.80: 100.0}
        self.assertAlmostEqual(paper_estimate.cost_at(costs, 0.75), 10.0, places=12)
        self.assertEqual(paper_estimate.cost_at(costs, 0.3), 1.0)
        self.assertEqual(paper_estimate.cost_at(costs, 0.9), 100.0)
        self.assertAlmostEqual(paper_estimate.cost_at(costs, 0.80), 100.0, places=10)

    def test_constant_costs_give_known_hours(self):
        # 3600 s per strain unit: one hour per strain unit, 1760 in all, 120 of them at nu = 0.79 and
        # 0.80 (six runs of 20); 1 us per grain-step
        # over 8 x 5e5 x 5000 grain-steps: 2e4 s = 5.6 h.
        out = run("--before", "0.7:3600,0.8:3600", "--after", "0.7:3600", "--incline-before", "1:1",
                  "--incline-after", "1:2")
        self.assertEqual(out.returncode, 0, out.stderr)
        self.assertIn("before: shear 1760 CPU h (nu >= 0.79: 120), inclines 6-6 CPU h", out.stdout)
        self.assertIn("after: shear 1760 CPU h (nu >= 0.79: 120), inclines 6-11 CPU h", out.stdout)

    def test_bad_input_is_refused(self):
        for args in (["--before", "x"], ["--before", "0.7:-1"]):
            out = run(*args, "--after", "0.7:1", "--incline-before", "1:2", "--incline-after", "1:2")
            self.assertEqual(out.returncode, 2)
            self.assertEqual(out.stdout, "")
            self.assertEqual(len(out.stderr.strip().splitlines()), 1, out.stderr)


if __name__ == "__main__":
    unittest.main()
