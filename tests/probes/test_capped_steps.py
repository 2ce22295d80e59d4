"""Known answers of bench/probes/capped_steps.py on constructed steps of two grains.

Two rows with opposite normals: equal normal impulses on both are a self-stress without
friction, of work -(b1 + b2)/2 per unit of sum P_n. Two rows whose normals are 180° - θ apart:
P_n = p on both with P_t = ±p·tan(θ/2) is a self-stress (no net impulse, no torque), within the
cones only if tan(θ/2) <= mu, and none exists without friction. Exit 77 (skipped) without SciPy.
"""
import math
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "bench", "probes"))
try:
    import scipy  # noqa: F401
except ImportError:
    print("SciPy missing: skipped", file=sys.stderr)
    sys.exit(77)
import capped_steps  # noqa: E402

UPSILON = 1e-9


class CappedSteps(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.dir.cleanup()

    def step(self, b1, b2, theta_deg=0.0, mu=0.4, extra=""):
        """Rows (0, 1) with normals (1, 0) and -(cos θ, sin θ), bounds b1 Υ and b2 Υ, b_t = 0."""
        t = math.radians(theta_deg)
        name = os.path.join(self.dir.name, f"step_{b1}_{b2}_{theta_deg}.txt")
        with open(name, "w") as f:
            f.write(f"# mu {mu} upsilon {UPSILON} residual {UPSILON} rows 2 bodies 2\n")
            f.write("B 0 0 0 1\nB 0 0 0 1\n" + extra)
            f.write(f"R 0 1 1 0 {b1 * UPSILON} 0 0.5 0 0\n")
            f.write(f"R 0 1 {-math.cos(t)} {-math.sin(t)} {b2 * UPSILON} 0 0.5 0 0\n")
        return capped_steps.analyse(name)

    def test_frictionless_self_stress_of_negative_work(self):
        r = self.step(3, 1)
        self.assertAlmostEqual(r["work0"], -2.0, places=6)
        self.assertAlmostEqual(r["work"], -2.0, places=6)
        self.assertEqual(r["self_stress_rows"], 2)

    def test_self_stresses_of_positive_work_only(self):
        r = self.step(-3, 1)  # the self-stress does work +1 per unit of sum P_n
        self.assertEqual((r["work0"], r["work"], r["rows"]), (0.0, 0.0, 2))

    def test_self_stress_only_with_friction(self):
        r = self.step(3, 1, theta_deg=30)  # tan 15° = 0.27 <= 0.4
        self.assertEqual(r["work0"], 0.0)
        self.assertAlmostEqual(r["work"], -2.0, places=6)
        self.assertEqual(r["self_stress_rows"], 2)
        r = self.step(3, 1, theta_deg=60)  # tan 30° = 0.58 > 0.4: outside the cones
        self.assertEqual((r["work0"], r["work"]), (0.0, 0.0))
        r = self.step(3, 1, theta_deg=60, mu=0.6)
        self.assertAlmostEqual(r["work"], -2.0, places=6)

    def test_not_a_dump(self):
        name = os.path.join(self.dir.name, "other.txt")
        with open(name, "w") as f:
            f.write("hello\n")
        with self.assertRaises(ValueError):
            capped_steps.analyse(name)
        with self.assertRaises(ValueError):
            self.step(3, 1, extra="X 1 2 3\n")


if __name__ == "__main__":
    unittest.main()
