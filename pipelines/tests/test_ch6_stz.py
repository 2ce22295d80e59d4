"""Chapter 6, STZ (thesis §6.3, Figs 6.9-6.11): d2min_maps.py on constructed gf-stz d2min outputs
with a known black set (fraction, clusters across the Lees–Edwards boundary and across x, Jaccard
exact), its refusals; the figure script on those and on a constructed gf-stz fit table; the
report section's numbers. Inputs are laid out as the issue-23 contract says (write_d2min,
write_fit)."""
import math
import os
import re
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

import synthetic  # a sibling module: the tests' own fixtures

from analysis import d2min_maps
from granflow import stz_table as st

PIPELINES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")

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
    4e-2 ⟨d⟩², the others 4e-4 ⟨d⟩² (grain 10: 4e-3, a sum of 4 over 1000 neighbours), `invalid`
    NaN and valid 0 (the default threshold is 1e-2 ⟨d⟩²)."""
    n = len(positions)
    neighbours = np.full(n, 6, dtype=np.int32)
    per = np.full(n, 4e-4 * mean_diameter**2)
    per[list(black)] = 4e-2 * mean_diameter**2
    neighbours[10] = 1000
    per[10] = 4e-3 * mean_diameter**2
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


def tan_theta_star(kappa, zeta):
    """The root of ζ t tanh(κt) = 1 by bisection (eq. 6.35)."""
    lo, hi = 0.0, 10.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if zeta * mid * math.tanh(kappa * mid) < 1 else (lo, mid)
    return 0.5 * (lo + hi)


# The fits of the synthetic table: μ = 0 at (A, κ, ζ) = (1, 5, 5), μ = 0.4 at (2, 3, 10).
FITS = {0.0: (1.0, 5.0, 5.0), 0.4: (2.0, 3.0, 10.0)}
RUN_COLUMNS = (
    "friction restitution packing_fraction rate_R_over_sqrt_T rate_R_over_sqrt_T_error s_over_p s_over_p_error "
    "inertial_number inertial_number_error xi_ratio prediction residual prediction_mu_of_I residual_mu_of_I"
).split()


def fit_rows(d):
    """Rows of /runs: μ = 0 e = 0 dense (fitted, on the curve), one dilute e = 0 run, e = 0.5 runs
    0.01 above the curve, μ = 0.4 e = 0 fitted, and one incline point per μ 0.02 below."""
    rows = []

    def row(kind, mu, e, nu, s_over_p, offset, dense, fitted, name):
        A, kappa, zeta = FITS[mu]
        x = float(st.stz_rate(A, kappa, zeta, s_over_p))
        rows.append(
            dict(
                input=os.path.join(d, name),
                input_sha256="0" * 64,
                kind=kind,
                friction=mu,
                restitution=e,
                packing_fraction=nu,
                rate_R_over_sqrt_T=x,
                rate_R_over_sqrt_T_error=0.01 * x,
                s_over_p=s_over_p + offset,
                s_over_p_error=0.002,
                inertial_number=0.5 * x,
                inertial_number_error=0.005 * x,
                xi_ratio=2.0 if dense else 1.1,
                dense=dense,
                fitted=fitted,
                prediction=s_over_p,
                residual=offset,
                prediction_mu_of_I=s_over_p + 0.003,
                residual_mu_of_I=offset - 0.003,
            )
        )

    for nu, mu_value in zip((0.78, 0.79, 0.80, 0.81), (0.25, 0.29, 0.34, 0.44)):
        row("shear", 0.0, 0.0, nu, mu_value, 0.0, 1, 1, f"shear_nu{nu:.3f}_e0.00_mu0.00_r1e-02_s1.h5")
    row("shear", 0.0, 0.0, 0.5, 0.6, 0.05, 0, 0, "shear_nu0.500_e0.00_mu0.00_r1e-02_s1.h5")
    for nu, mu_value in zip((0.79, 0.80), (0.27, 0.31)):
        row("shear", 0.0, 0.5, nu, mu_value, 0.01, 1, 0, f"shear_nu{nu:.3f}_e0.50_mu0.00_r1e-02_s1.h5")
    for nu, mu_value in zip((0.74, 0.76, 0.78), (0.3, 0.4, 0.5)):
        row("shear", 0.4, 0.0, nu, mu_value, 0.0, 1, 1, f"shear_nu{nu:.3f}_e0.00_mu0.40_r1e-02_s1.h5")
    row("incline", 0.0, 0.0, 0.81, 0.26, -0.02, 1, 0, "incline_th14_e0.00_mu0.00_s1.h5")
    row("incline", 0.4, 0.0, 0.79, 0.36, -0.02, 1, 0, "incline_branch_th20_e0.00_mu0.40_s1_from14.h5")
    return rows


def write_fit(path, rows):
    """A gf-stz fit output (contract schema) with the fits of FITS and the given /runs rows."""
    with h5py.File(path, "w") as f:
        f.create_group("parameters").attrs.update({"program": "gf-stz", "command": "fit"})
        g = f.create_group("runs")
        for name in ("input", "input_sha256", "kind"):
            g.create_dataset(name, data=np.array([r[name] for r in rows], dtype=object), dtype=h5py.string_dtype())
        for name in RUN_COLUMNS:
            g[name] = np.array([r[name] for r in rows], dtype=float)
        for name in ("dense", "fitted"):
            g[name] = np.array([r[name] for r in rows], dtype=np.uint8)
        fit = f.create_group("fit")
        fit.attrs.update(
            {
                "objective": "least-squares",
                "fit_restitution": 0.0,
                "dense_rule": "xi_ratio >= 1.25",
                "theta_star_units": "degrees",
            }
        )
        mus = sorted(FITS)
        t = [tan_theta_star(FITS[m][1], FITS[m][2]) for m in mus]
        columns = {
            "friction": mus,
            "A": [FITS[m][0] for m in mus],
            "A_error": [0.1, 0.2],
            "kappa": [FITS[m][1] for m in mus],
            "kappa_error": [0.2, 0.3],
            "zeta": [FITS[m][2] for m in mus],
            "zeta_error": [0.5, 1.0],
            "tan_theta_star": t,
            "tan_theta_star_error": [0.004, 0.005],
            "theta_star": [math.degrees(math.atan(v)) for v in t],
            "theta_star_error": [0.2, 0.3],
            "chi2": [2.0, 1.0],
            "mu_s": [0.2, 0.18],
            "mu_s_error": [0.01, 0.02],
            "mu_2": [0.6, 0.7],
            "mu_2_error": [0.05, 0.06],
            "I0": [0.3, 0.4],
            "I0_error": [0.03, 0.04],
            "stz_rms": [0.001, 0.002],
            "mu_of_I_rms": [0.003, 0.001],
            "predicted_rms": [0.01, NAN],
            "incline_rms": [0.02, 0.02],
            "mu_of_I_predicted_rms": [0.007, NAN],
            "mu_of_I_incline_rms": [0.023, 0.023],
        }
        for name, values in columns.items():
            fit[name] = np.array(values, dtype=float)
        fit["points"] = np.array([4, 3], dtype=np.int64)
        fit["dof"] = np.array([1, 0], dtype=np.int64)
        fit["predicted_count"] = np.array([3, 0], dtype=np.int64)
        fit["incline_count"] = np.array([1, 1], dtype=np.int64)
    return path


def write_critical(path, theta_c=11.5, half=0.5, restitution=0.5):
    """The parts of a critical_angle.py table the report reads."""
    with h5py.File(path, "w") as f:
        f.create_group("parameters").attrs["program"] = "critical_angle.py"
        g = f.create_group("runs")
        g["angle"] = np.array([11.0, 12.0])
        g["friction"] = np.array([0.0, 0.0])
        g["restitution"] = np.array([restitution, restitution])
        c = f.create_group("critical_angle")
        c.attrs.update(
            {"theta_c": theta_c, "theta_below": theta_c - half, "theta_above": theta_c + half, "half_width": half}
        )
    return path


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
        # Grain 10: a sum of 4 (large) but 4e-3 ⟨d⟩² per neighbour, below 1e-2: not black.
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
        np.testing.assert_allclose(t[[0, 4, 8]], [1e-3, 1e-2, 1e-1], rtol=1e-12)
        frac = sweep["black_fraction"]
        np.testing.assert_allclose(frac[:, 4], self.table["default"]["black_fraction"], rtol=1e-15)
        # At 1e-3 ⟨d⟩² grain 10 (4e-3 per neighbour) is black in every map too; at 1e-1 none is.
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


class MapStatisticsKnownAnswers(unittest.TestCase):
    """d2min_statistics.py (the convergence study's D²min table of one run) on two constructed
    pairs of maps: every statistic and its error over the pairs by hand, and its refusals."""

    def run_statistics(self, *args):
        return subprocess.run(
            [sys.executable, os.path.join(PIPELINES, "analysis", "d2min_statistics.py"), *args],
            capture_output=True, text=True,
        )

    def test_pairs(self):
        with tempfile.TemporaryDirectory() as d:
            # Pair 1: 8 and 5 of 15 valid grains black, 3 of a union of 10 shared; largest
            # clusters 3 ({4, 5, 6}) and 2 ({4, 5}); medians 4e-2 and 4e-4. Pair 2: 9 and 2 black,
            # none shared; largest clusters 3 and 1; medians 4e-2 and 4e-4.
            paths = [os.path.join(d, f"m{k}.h5") for k in range(4)]
            for path, black in zip(paths, (BLACK_A, [3, 4, 5, 11, 12], BLACK_A + [11], [12, 13])):
                write_d2min(path, black)
            out = os.path.join(d, "stats.h5")
            res = self.run_statistics("-o", out, *paths)
            self.assertEqual(res.returncode, 0, res.stderr)
            with h5py.File(out, "r") as f:
                r = {k: float(f["runs"][k][0]) for k in f["runs"] if k not in ("input", "input_sha256")}
                self.assertEqual(f["runs/input"][0].decode(), "traj.h5")
                self.assertEqual(f["parameters"].attrs["pairs"], 2)
            expected = {
                "black_fraction": (12 / 30, 1 / 30),
                "d2min_median": ((4e-2 + 4e-4) / 2, 0.0),
                "largest_cluster": (2.25, 0.25),
                "jaccard": (0.15, 0.15),
                "interval": (0.05, None),
            }
            for name, (value, error) in expected.items():
                self.assertAlmostEqual(r[name], value, places=12, msg=name)
                if error is not None:
                    self.assertAlmostEqual(r[name + "_error"], error, places=12, msg=name)
            # Chance: pq/(p + q − pq) per pair, averaged.
            chance = [p * q / (p + q - p * q) for p, q in ((8 / 15, 5 / 15), (9 / 15, 2 / 15))]
            self.assertAlmostEqual(r["jaccard_chance"], np.mean(chance), places=12)

    def test_refusals(self):
        with tempfile.TemporaryDirectory() as d:
            paths = [os.path.join(d, f"m{k}.h5") for k in range(4)]
            for path in paths:
                write_d2min(path, BLACK_A)
            with h5py.File(paths[3], "a") as f:
                f["parameters"].attrs["input"] = "other.h5"
            write_d2min(paths[2], BLACK_A, strain=0.1)
            out = os.path.join(d, "stats.h5")
            for maps, needle in ((paths[:3], "pairs"), (paths[:2] + [paths[3], paths[0]], "one run"),
                                 (paths[:3] + [paths[0]], "intervals")):
                res = self.run_statistics("-o", out, *maps)
                self.assertEqual(res.returncode, 2, res.stderr)
                self.assertEqual(len(res.stderr.strip().splitlines()), 1, res.stderr)
                self.assertIn(needle, res.stderr)
                self.assertFalse(os.path.exists(out))


class FitTableAndCurve(unittest.TestCase):
    def test_curve_starts_at_tan_theta_star_and_follows_eq_6_36(self):
        with tempfile.TemporaryDirectory() as d:
            table = st.read_table(write_fit(os.path.join(d, "fit.h5"), fit_rows(d)))
            row = st.fit_row(table, 0.0)
            x, mu = st.curve(table, row, 4.6365)
            self.assertEqual(x[0], 0.0)
            self.assertAlmostEqual(mu[0], 0.23994, places=5)
            # Known values of (1, 5, 5) (REFERENCES.md): x(0.54) = 4.6365 is the last point.
            self.assertAlmostEqual(float(np.interp(2.3797, x, mu)), 0.44, places=3)
            self.assertLessEqual(x[-1], 4.6365)
            self.assertGreater(mu[-1], 0.53)
            self.assertIsNone(st.fit_row(table, 0.1))

    def test_not_a_fit_table(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "x.h5")
            with h5py.File(path, "w") as f:
                f.create_group("runs")
            with self.assertRaises(SystemExit) as cm:
                st.read_table(path)
            self.assertIn("x.h5", str(cm.exception))


class Ch6StzOutputs(unittest.TestCase, synthetic.ScriptRunner):
    """The figure script draws the three figures and the report writes both sections with the
    tables' numbers."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = cls.tmp.name
        cls.fit = write_fit(os.path.join(d, "ch6_stz.h5"), fit_rows(d))
        cls.critical = write_critical(os.path.join(d, "critical.h5"))
        inputs = [os.path.join(d, f"map_{k}.h5") for k in "abcd"]
        write_d2min(inputs[0], BLACK_A)
        write_d2min(inputs[1], [3, 4, 5, 11, 12])
        write_d2min(inputs[2], BLACK_A + [11], strain=0.15)
        write_d2min(inputs[3], [12, 13], strain=-0.05)
        cls.maps = os.path.join(d, "maps.h5")
        res = run_maps("--start-strain", "0,0.1,0,0", "-o", cls.maps, *inputs)
        if res.returncode != 0:
            raise AssertionError(res.stderr)
        packing = synthetic.write_packing(os.path.join(d, "pack.h5"))
        out = os.path.join(d, "REPORT.md")
        res = subprocess.run(
            [
                sys.executable,
                os.path.join(PIPELINES, "report"),
                "--size",
                "test",
                "--output",
                out,
                "--ch6-stz",
                cls.fit,
                "--ch6-d2min",
                cls.maps,
                packing,
            ],
            capture_output=True,
            text=True,
        )
        cls.report = f"the report failed:\n{res.stderr}"
        if res.returncode == 0:
            with open(out) as fh:
                cls.report = fh.read()
        # The same with the critical-angle table (it needs the incline table beside it: the
        # section function is called directly instead).
        from report import ch6_stz  # noqa: E402  (pipelines/ is on the path of these tests)

        cls.with_critical = "\n".join(ch6_stz.stz_section(cls.fit, cls.critical))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_figures(self):
        for figure, source in (("6.9", self.maps), ("6.10", self.fit), ("6.11", self.fit)):
            out = os.path.join(self.tmp.name, f"fig{figure.replace('.', '_')}.png")
            with self.subTest(figure=figure):
                self.run_script("plot/ch6_stz.py", "--figure", figure, source, out)
                with open(out, "rb") as fh:
                    self.assertEqual(fh.read(8), b"\x89PNG\r\n\x1a\n")

    def test_d2min_section(self):
        r = self.report
        self.assertIn("## Chapter 6: non-affine motion, D²min (thesis §6.3, Fig. 6.9)", r)
        # Map a: 8 of 15 valid grains black, 4 clusters, the largest of 3, sizes 1×1, 2×2, 1×3.
        self.assertIn("| (a) | 0 → 0.05 | 16 (15) | 53.3 % | 4 | 3 | 2 | 1×1, 2×2, 1×3 | 0.0 % – 60.0 % |", r)
        self.assertIn("| (b) | 0.1 → 0.15 | 16 (15) | 33.3 % |", r)
        # Jaccard a-b = 3/10, chance pq/(p + q − pq) with p = 8/15, q = 5/15 (= 0.2581).
        self.assertIn("| a-b | 0.3 | 0.258 | 1.16 |", r)
        self.assertIn("| a-c | 0.889 |", r)
        self.assertIn("| a-d | 0 |", r)

    def test_stz_section(self):
        r = self.report
        self.assertIn("## Chapter 6: the STZ constitutive law (thesis §6.3, Figs 6.10–6.11)", r)
        self.assertIn("| 0 | 4 | 1 ± 0.1 | 5 ± 0.2 | 5 ± 0.5 | 0.24 ± 0.004 | 13.5 ± 0.2 | – | 2/1 |", r)
        self.assertIn("| 0.4 | 3 | 2 ± 0.2 | 3 ± 0.3 | 10 ± 1 | 0.192 ± 0.005 |", r)
        self.assertIn("| 0 | 0.001 | 0.003 | STZ | 0.01 (3) | 0.007 (3) | 0.02 (1) | 0.023 (1) |", r)
        self.assertIn("| 0.4 | 0.002 | 0.001 | μ(I) | – (0) |", r)
        # Split by the dense rule: the two e = 0.5 rows (dense, 0.01 above) and the dilute e = 0 row.
        self.assertIn("| 0 | 0.01 (2) | 0.007 (2) | 0.05 (1) | 0.047 (1) |", r)
        self.assertIn("| 0.4 | – (0) | – (0) | – (0) | – (0) |", r)
        self.assertIn("| `incline_th14_e0.00_mu0.00_s1.h5` | 0 | 0 |", r)
        self.assertIn("| 0.26 | -0.02 | -0.023 |", r)
        self.assertNotIn("critical angle", r)

    def test_theta_star_against_critical_angle(self):
        theta = math.degrees(math.atan(tan_theta_star(5.0, 5.0)))
        self.assertIn(
            f"θ* (μ = 0) = {theta:.3g} ± 0.2° against the incline's critical angle θ_c = 11.5° ± 0.5°",
            self.with_critical,
        )
        self.assertIn(f"difference {theta - 11.5:.3g}°", self.with_critical)
        self.assertIn("Note: the critical-angle sweep is at e = 0.5, the fit at e = 0.", self.with_critical)

    def test_degenerate_coefficients_use_the_jackknife(self):
        # A μ = 0 fit whose A, κ, ζ run off (errors ~10¹³ times the values) and whose delta-method
        # θ* error is NaN, as the quick size's: the jackknife error is shown and used against θ_c.
        from report import ch6_stz  # noqa: E402

        with tempfile.TemporaryDirectory() as d:
            path = write_fit(os.path.join(d, "fit.h5"), fit_rows(d))
            with h5py.File(path, "r+") as f:
                f["fit/A_error"][0] = 1e20
                f["fit/tan_theta_star_error"][0] = NAN
                f["fit/theta_star_error"][0] = NAN
                f["fit/theta_star_jackknife_error"] = np.array([0.75, 0.4])
            text = "\n".join(ch6_stz.stz_section(path, self.critical))
        self.assertIn("| 0.24 | 13.5 | 0.75 | 2/1 |", text)
        self.assertIn("At μ = 0 A, κ and ζ are not determined one by one", text)
        self.assertNotIn("At μ = 0, 0.4", text)
        theta = math.degrees(math.atan(tan_theta_star(5.0, 5.0)))
        self.assertIn(f"θ* (μ = 0) = {theta:.3g} ± 0.75° against", text)


ROOT = os.path.abspath(os.path.join(PIPELINES, ".."))


class Ch6StzMake(unittest.TestCase):
    """The STZ part of pipelines/ch6.mk, dry run at SIZE=test with stamps present: the branches'
    commands, the maps' frames computed from the strains, the fit's runs and incline table, the
    figures and the report's arguments. Nothing is built or run."""

    def dry_run(self, *targets, expect=0, **variables):
        with tempfile.TemporaryDirectory() as d:
            stamps = os.path.join(d, "build", "stamps")
            os.makedirs(stamps)
            for prog in ("gf-pack", "gf-shear", "gf-incline", "gf-stz", "gf-correlate", "libgranflow_statistics.so"):
                with open(os.path.join(stamps, prog + ".stamp"), "w") as fh:
                    fh.write("0\n")
            args = synthetic.scratch_make(d, "-n") + [f"{k}={v}" for k, v in variables.items()]
            args += [t.replace("TMP", d) for t in targets]
            res = subprocess.run(args, cwd=ROOT, capture_output=True, text=True)
            self.assertEqual(res.returncode, expect, res.stderr)
            return re.sub(r"[ \t]+", " ", (res.stdout + res.stderr).replace(d, "TMP").replace("\\\n", " "))

    def test_maps_and_branches(self):
        out = self.dry_run("ch6-files")
        stem = "nu0.700_e0.00_mu0.00_r1e-02_s1.h5"
        for name, rate, strain in (("forward", "1e-02", "0.15"), ("backward", "-1e-02", "0.05")):
            self.assertIn(
                f"gf-shear --quiet -i TMP/runs/shear_{stem} --frame -1 -o TMP/runs/d2min_{name}_{stem} --rate {rate} "
                f"--restitution 0.00 --friction 0.00 --seed 1 --strain {strain} --strain-step 1e-3 --frame-every 10",
                out,
            )
        d2min = "gf-stz d2min --quiet --cutoff 2 -o TMP/runs/ch6_d2min_"
        # A frame every 10 steps of 1e-3: strain 0.05 is frame 5, 0.10 frame 10, 0.15 frame 15.
        self.assertIn(f"{d2min}a.h5 -i TMP/runs/shear_{stem} --branch TMP/runs/d2min_forward_{stem} --frames -1,5", out)
        self.assertIn(f"{d2min}b.h5 -i TMP/runs/d2min_forward_{stem} --frames 10,15", out)
        self.assertIn(
            f"{d2min}c.h5 -i TMP/runs/shear_{stem} --branch TMP/runs/d2min_forward_{stem} --frames -1,15", out
        )
        self.assertIn(
            f"{d2min}d.h5 -i TMP/runs/shear_{stem} --branch TMP/runs/d2min_backward_{stem} --frames -1,5", out
        )
        self.assertRegex(
            out,
            r"d2min_maps\.py --start-strain 0,0\.1,0,0 -o TMP/runs/ch6_d2min_maps\.h5 "
            r"TMP/runs/ch6_d2min_a\.h5 TMP/runs/ch6_d2min_b\.h5 TMP/runs/ch6_d2min_c\.h5 TMP/runs/ch6_d2min_d\.h5",
        )
        for k in (9, 10, 11):
            self.assertIn(f"ch6_stz.py --figure 6.{k} ", out)

    def test_fit_runs_and_incline(self):
        out = self.dry_run("ch6-files")
        # e = 0 incline runs: μ = 0 from the pack, μ = 0.4 branched from it.
        self.assertIn("-o TMP/runs/incline_th20_e0.00_mu0.00_s1.h5 --angle 20 --restitution 0.00 --friction 0.00", out)
        self.assertIn(
            "gf-incline --quiet -i TMP/runs/incline_th20_e0.00_mu0.00_s1.h5 -o "
            "TMP/runs/incline_branch_th30_e0.00_mu0.40_s1_from20.h5 --angle 30 --restitution 0.00 --friction 0.40",
            out,
        )
        self.assertRegex(
            out,
            r"incline_bulk\.py --base-skip 1 --surface-skip 1 -o TMP/runs/ch6_incline\.h5 "
            r"TMP/runs/incline_th20_e0\.00_mu0\.00_s1\.h5 TMP/runs/incline_branch_th30_e0\.00_mu0\.40_s1_from20\.h5",
        )
        prefix = (
            "gf-stz fit --quiet -o TMP/runs/ch6_stz.h5 --min-packing-fraction 0.55 --incline TMP/runs/ch6_incline.h5 "
            "--from-strain 0.05 --detect-transient "
        )
        self.assertIn(prefix, out)
        args = out[out.index(prefix) + len(prefix) :].split("\n")[0].split()
        runs = [os.path.basename(a) for a in args]
        expected = [
            f"shear_nu{nu}_e{e}_mu0.00_r1e-02_s1.h5"
            for e in ("0.00", "0.92")
            for nu in ("0.700", "0.740", "0.760", "0.780", "0.800")
        ]
        expected += [f"shear_nu{nu}_e0.00_mu0.40_r1e-02_s1.h5" for nu in ("0.600", "0.700", "0.740", "0.760")]
        self.assertEqual(runs, expected)
        out = self.dry_run("TMP/figures/REPORT.md")
        self.assertRegex(out, r"pipelines/report .*--ch6-stz TMP/runs/ch6_stz\.h5 --ch6-d2min TMP/runs/ch6_d2min_maps\.h5")

    def test_correlation_table_when_given(self):
        out = self.dry_run("ch6-files", CH6_STZ_CORRELATION="$(RUNS)/ch5_correlate.h5")
        self.assertRegex(out, r"gf-stz fit --quiet -o TMP/runs/ch6_stz\.h5 --correlation TMP/runs/ch5_correlate\.h5 ")

    def test_strain_not_a_whole_number_of_frames(self):
        out = self.dry_run("ch6-files", expect=2, CH6_STZ_FRAME_EVERY=7)
        self.assertIn("strain 0.05 is not a whole number of frames of 7 steps of 1e-3", out)


if __name__ == "__main__":
    unittest.main()
