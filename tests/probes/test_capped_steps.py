"""Known answers of bench/probes/capped_steps.py on constructed steps.

Two grains and two rows between them with opposite normals: equal normal impulses on both rows
are a self-stress (no net impulse, no torque), whose work per unit of sum P_n is -(b1 + b2)/2,
and the normal constraints u1 >= b1, u2 = -u1 >= b2 can be met only if b1 + b2 <= 0, else
at best within t = (b1 + b2)/2 of both. Exit 77 (skipped) without SciPy.
"""
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


def write_step(directory, b1, b2, pn1=0.0, mu=0.4):
    """The two-row step; pn1 on the first row, the grains' velocities including its impulse."""
    name = os.path.join(directory, f"step_{b1}_{b2}_{pn1}.txt")
    with open(name, "w") as f:
        f.write(f"# mu {mu} upsilon {UPSILON} residual {UPSILON} rows 2 bodies 2\n")
        f.write(f"B {pn1} 0 0 1\nB {-pn1} 0 0 1\n")
        f.write(f"R 0 1 1 0 {b1 * UPSILON} 0 0.5 {pn1} 0\n")
        f.write(f"R 0 1 -1 0 {b2 * UPSILON} 0 0.5 0 0\n")
    return name


class CappedSteps(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.dir.cleanup()

    def test_self_stress_of_negative_work(self):
        for pn1 in (0.0, 1.0):  # the impulses held do not change the answers
            r = capped_steps.analyse(write_step(self.dir.name, 3, 1, pn1))
            self.assertAlmostEqual(r["feasible"], 2.0, places=6)
            self.assertAlmostEqual(r["work"], -2.0, places=6)
            self.assertAlmostEqual(r["work0"], -2.0, places=6)
            self.assertEqual(r["self_stress_rows"], 2)

    def test_solvable(self):
        r = capped_steps.analyse(write_step(self.dir.name, -3, 1))
        self.assertEqual(r["feasible"], 0.0)
        self.assertEqual(r["work"], 0.0)  # the only self-stress does positive work, +1
        self.assertEqual(r["work0"], 0.0)
        self.assertEqual(r["rows"], 2)

    def test_not_a_dump(self):
        name = os.path.join(self.dir.name, "other.txt")
        with open(name, "w") as f:
            f.write("hello\n")
        with self.assertRaises(ValueError):
            capped_steps.analyse(name)


if __name__ == "__main__":
    unittest.main()
