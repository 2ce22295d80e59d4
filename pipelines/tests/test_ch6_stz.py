"""Chapter 6, STZ (thesis §6.3, Figs 6.9-6.11): d2min_maps.py on constructed gf-stz d2min outputs
with a known black set (fraction, clusters across the Lees–Edwards boundary and across x, Jaccard
exact), its refusals; the figure script on those and on a constructed gf-stz fit table; the
report section's numbers. Inputs are laid out as the issue-23 contract says (write_d2min,
write_fit)."""
import math
import os
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

import synthetic  # a sibling module: the tests' own fixtures

PIPELINES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, os.path.join(PIPELINES, "analysis"))
import d2min_maps  # noqa: E402

NAN = float("nan")
BOX = (10.0, 10.0)
# Reference positions (radius 0.5, contact distance 1, joined below 1.1 at the default gap):
# 0, 1: across the Lees–Edwards boundary (1's image one period up, shifted by the offset 3, lies
#       0.4 above 0; without the offset they are 3 apart);
# 2, 3: across x (0.2 and 9.7: 0.5 apart through x = 0);
# 4, 5, 6: a chain along x at y = 3, step 0.9;
# 7: a lone grain; 8: white, touching 4 (must not join anything);
# 9: invalid (singular fit) touching 7; 10: a large sum but a small value per neighbour;
# 11-15: white, far from everything.
POSITIONS = np.array(
    [
        [2.0, 9.8],
        [9.0, 0.2],
        [0.2, 5.0],
        [9.7, 5.0],
        [4.0, 3.0],
        [4.9, 3.0],
        [5.8, 3.0],
        [6.0, 7.0],
        [4.0, 4.0],
        [6.9, 7.0],
        [2.0, 2.0],
        [7.5, 1.5],
        [2.0, 7.0],
        [7.0, 5.0],
        [5.0, 5.5],
        [8.0, 8.8],
    ]
)
N = len(POSITIONS)
BLACK_A = [0, 1, 2, 3, 4, 5, 6, 7]


def write_d2min(path, black, strain=0.05, offset=3.0, positions=POSITIONS, invalid=(9,), mean_diameter=1.0):
    """A gf-stz d2min output (contract schema): grains of `black` get a D²min per neighbour of
    1e-2 ⟨d⟩², the others 1e-4 ⟨d⟩² (grain 10: a sum of 1 over 1000 neighbours), `invalid` NaN and
    valid 0."""
    n = len(positions)
    neighbours = np.full(n, 6, dtype=np.int32)
    per = np.full(n, 1e-4 * mean_diameter**2)
    per[list(black)] = 1e-2 * mean_diameter**2
    neighbours[10] = 1000
    per[10] = 1e-3 * mean_diameter**2
    valid = np.ones(n, dtype=np.uint8)
    valid[list(invalid)] = 0
    per[list(invalid)] = NAN
    neighbours[list(invalid)] = 1
    with h5py.File(path, "w") as f:
        p = f.create_group("parameters")
        p.attrs.update({"program": "gf-stz", "command": "d2min", "input": "traj.h5"})
        d = f.create_group("d2min")
        d["value"] = per * neighbours
        d["per_neighbour"] = per
        d["neighbours"] = neighbours
        d["valid"] = valid
        F = np.tile(np.eye(2), (n, 1, 1))
        F[valid == 0] = NAN
        d["F"] = F
        d.attrs.update(
            {
                "cutoff": 2.0 * mean_diameter,
                "cutoff_diameters": 2.0,
                "mean_diameter": mean_diameter,
                "reference_frame": np.int64(100),
                "current_frame": np.int64(10),
                "current_source": "branch",
                "reference_time": 500.0,
                "current_time": 5.0,
                "strain": strain,
                "offset_change": strain * BOX[1],
                "valid_count": np.int64(int(valid.sum())),
            }
        )
        r = f.create_group("reference")
        r["position"] = positions
        r["radius"] = np.full(n, 0.5 * mean_diameter)
        r.attrs["box"] = np.array(BOX) * mean_diameter
        r.attrs["offset"] = offset * mean_diameter


def run_maps(*args):
    return subprocess.run(
        [sys.executable, os.path.join(PIPELINES, "analysis", "d2min_maps.py"), *args], capture_output=True, text=True
    )


class MapsKnownAnswers(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = cls.tmp.name
        cls.inputs = [os.path.join(d, f"map_{k}.h5") for k in "abcd"]
        write_d2min(cls.inputs[0], BLACK_A)
        write_d2min(cls.inputs[1], [3, 4, 5, 11, 12], strain=0.05)  # overlap 3 of union 10
        write_d2min(cls.inputs[2], BLACK_A + [11], strain=0.15)  # overlap 8 of 9
        write_d2min(cls.inputs[3], [12, 13], strain=-0.05)  # no overlap
        cls.out = os.path.join(d, "maps.h5")
        res = run_maps("--start-strain", "0,0.1,0,0", "-o", cls.out, *cls.inputs)
        if res.returncode != 0:
            raise AssertionError(res.stderr)
        cls.table = d2min_maps.read_table(cls.out)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_black_fraction_counts_valid_grains(self):
        default = self.table["default"]
        self.assertEqual(list(default["black_count"]), [8, 5, 9, 2])
        # 16 grains, one invalid: fractions over 15.
        np.testing.assert_allclose(default["black_fraction"], np.array([8, 5, 9, 2]) / 15, rtol=1e-15)
        black = self.table["maps"]["black"]
        self.assertEqual(list(np.flatnonzero(black[0])), BLACK_A)
        # Grain 10: a sum of 1 (large) but 1e-3 ⟨d⟩² per neighbour, below 2.5e-3: not black.
        self.assertFalse(black[0][10])

    def test_clusters_across_both_boundaries(self):
        default = self.table["default"]
        # Map a: {0, 1} across the Lees–Edwards boundary, {2, 3} across x, {4, 5, 6}, {7}.
        self.assertEqual(int(default["cluster_count"][0]), 4)
        self.assertEqual(int(default["largest_cluster"][0]), 3)
        np.testing.assert_array_equal(default["cluster_size_histogram"][0], [1, 2, 1])
        self.assertAlmostEqual(float(default["mean_cluster_size"][0]), 2.0)
        # Map b: {3}, {4, 5}, {11}, {12}.
        np.testing.assert_array_equal(default["cluster_size_histogram"][1][:3], [3, 1, 0])

    def test_jaccard_exact_and_chance(self):
        default = self.table["default"]
        self.assertEqual(list(default["pair"]), ["a-b", "a-c", "a-d"])
        np.testing.assert_allclose(default["jaccard"], [3 / 10, 8 / 9, 0.0], rtol=1e-15)
        p = 8 / 15
        expected = [(p * q) / (p + q - p * q) for q in (5 / 15, 9 / 15, 2 / 15)]
        np.testing.assert_allclose(default["jaccard_chance"], expected, rtol=1e-12)

    def test_strains_and_reference_copied(self):
        maps = self.table["maps"]
        self.assertEqual(list(maps["label"]), ["a", "b", "c", "d"])
        np.testing.assert_allclose(maps["start_strain"], [0, 0.1, 0, 0])
        np.testing.assert_allclose(maps["end_strain"], [0.05, 0.15, 0.15, -0.05])
        np.testing.assert_array_equal(maps["position"][0], POSITIONS)
        self.assertEqual(list(self.table["runs"]["input"]), self.inputs)
        self.assertTrue(math.isnan(maps["d2min_scaled"][0][9]))

    def test_sweep(self):
        sweep = self.table["sweep"]
        t = sweep["threshold"]
        self.assertEqual(len(t), 9)
        np.testing.assert_allclose(t[[0, 4, 8]], [2.5e-4, 2.5e-3, 2.5e-2], rtol=1e-12)
        frac = sweep["black_fraction"]
        np.testing.assert_allclose(frac[:, 4], self.table["default"]["black_fraction"], rtol=1e-15)
        # At 2.5e-4 ⟨d⟩² grain 10 (1e-3 per neighbour) is black in every map too; above 1e-2 none is.
        np.testing.assert_allclose(frac[:, 0], np.array([9, 6, 10, 3]) / 15, rtol=1e-15)
        np.testing.assert_allclose(frac[:, 8], [0.0, 0.0, 0.0, 0.0])
        self.assertTrue(np.all(np.isnan(sweep["jaccard"][:, 8])))
        np.testing.assert_allclose(sweep["jaccard"][:, 0], [4 / 11, 9 / 10, 1 / 11], rtol=1e-15)
        # Nested black sets: the fraction never grows with the threshold.
        self.assertTrue(np.all(np.diff(frac, axis=1) <= 0))


class MapsLeesEdwards(unittest.TestCase):
    """The offset enters the minimum image: with the offset 13 (past L_x, the same boundary as 3)
    grains 0 and 1 still join; with offset 0 they are 3 apart and do not."""

    def clusters(self, offset):
        with tempfile.TemporaryDirectory() as d:
            path, out = os.path.join(d, "a.h5"), os.path.join(d, "m.h5")
            write_d2min(path, BLACK_A, offset=offset)
            res = run_maps("-o", out, path)
            self.assertEqual(res.returncode, 0, res.stderr)
            return d2min_maps.read_table(out)["default"]["cluster_size_histogram"][0]

    def test_offset_wrapped_past_lx(self):
        np.testing.assert_array_equal(self.clusters(13.0), [1, 2, 1])

    def test_offset_matters(self):
        np.testing.assert_array_equal(self.clusters(0.0), [3, 1, 1])

    def test_units_of_mean_diameter(self):
        # Everything scaled by ⟨d⟩ = 3: the same black set and clusters.
        with tempfile.TemporaryDirectory() as d:
            path, out = os.path.join(d, "a.h5"), os.path.join(d, "m.h5")
            write_d2min(path, BLACK_A, offset=3.0, positions=POSITIONS * 3, mean_diameter=3.0)
            res = run_maps("-o", out, path)
            self.assertEqual(res.returncode, 0, res.stderr)
            default = d2min_maps.read_table(out)["default"]
            self.assertEqual(int(default["black_count"][0]), 8)
            np.testing.assert_array_equal(default["cluster_size_histogram"][0], [1, 2, 1])


class MapsRefusals(unittest.TestCase):
    """Bad input: exit 2, one line naming the file, no output left behind."""

    def refused(self, paths, *extra):
        d = os.path.dirname(paths[0])
        out = os.path.join(d, "maps.h5")
        res = run_maps(*extra, "-o", out, *paths)
        self.assertEqual(res.returncode, 2, res.stderr)
        self.assertEqual(len(res.stderr.strip().splitlines()), 1, res.stderr)
        self.assertTrue(res.stderr.startswith("d2min_maps.py: error: "), res.stderr)
        self.assertEqual([n for n in os.listdir(d) if n.startswith(".maps") or n == "maps.h5"], [])
        return res.stderr

    def test_missing_file(self):
        with tempfile.TemporaryDirectory() as d:
            self.assertIn("nothere.h5", self.refused([os.path.join(d, "nothere.h5")]))

    def test_not_a_d2min_output(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "x.h5")
            with h5py.File(path, "w") as f:
                f.create_group("parameters")
            self.assertIn("/d2min/per_neighbour", self.refused([path]))

    def test_truncated(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "a.h5")
            write_d2min(path, BLACK_A)
            size = os.path.getsize(path)
            with open(path, "r+b") as f:
                f.truncate(size // 2)
            self.assertIn("a.h5", self.refused([path]))

    def test_not_the_same_grains(self):
        with tempfile.TemporaryDirectory() as d:
            a, b = os.path.join(d, "a.h5"), os.path.join(d, "b.h5")
            write_d2min(a, BLACK_A)
            write_d2min(b, [1], positions=POSITIONS[:12])
            self.assertIn("not the same grains", self.refused([a, b]))

    def test_bad_threshold_and_strains(self):
        with tempfile.TemporaryDirectory() as d:
            a = os.path.join(d, "a.h5")
            write_d2min(a, BLACK_A)
            self.assertIn("--threshold", self.refused([a], "--threshold", "0"))
            self.assertIn("--start-strain", self.refused([a], "--start-strain", "0,0.1"))


if __name__ == "__main__":
    unittest.main()
