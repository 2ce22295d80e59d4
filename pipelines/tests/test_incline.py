"""Tests of the incline analyses (incline_bulk.py, critical_angle.py), their figures (Figs
4.7-4.10) and the report's incline section, on synthetic gf-incline trajectories whose answers
are known: an ideal Bagnold layer (V_x = V_s − c(H − y)^a, invariants constant in the bulk,
stresses balancing the weight), flow-rate series at rest, steady, accelerating and slowing."""
import math
import os
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

from analysis import critical_angle as ca
from analysis import incline_bulk as ib
from analysis import steady_state as ss

import synthetic  # a sibling module: the tests' own fixtures

PIPELINES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")

TAU = math.sqrt(0.7)  # √(⟨R⟩/g) of the synthetic runs


def noise(n, scale, seed):
    return scale * np.random.default_rng(seed).normal(size=n)


class InclineBulkTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)

    def run_of(self, angle, **kw):
        path = os.path.join(self.tmp.name, f"incline_{angle}_{len(os.listdir(self.tmp.name))}.h5")
        synthetic.write_incline_run(path, angle, **kw)
        return ib.read_run(path)

    def test_bagnold_layer(self):
        run = self.run_of(12, profiles=synthetic.bagnold_profiles(12, exponent=1.5))
        row = ib.analyse_run(run, base_skip=3, surface_skip=8)
        self.assertEqual(row["flowing"], 1)
        d = 1.4
        self.assertAlmostEqual(row["surface_height"] / d, 25.0, delta=0.05)
        # Bulk: centres 4.5, 7.5, 10.5, 13.5, 16.5 diameters (base layer and top 8 diameters out).
        self.assertEqual(row["bulk_layers"], 5)
        self.assertAlmostEqual(row["bulk_from"] / d, 4.5)
        self.assertAlmostEqual(row["s_over_p"], math.tan(math.radians(12)), places=12)
        self.assertAlmostEqual(row["mT_over_pR2"], 0.05, places=12)
        self.assertLess(abs(row["inertial_drift"]), 1e-9)
        self.assertLess(row["yy_max_deviation"], 1e-9)
        self.assertLess(row["xy_max_deviation"], 1e-9)
        self.assertAlmostEqual(row["velocity_exponent"], 1.5, delta=2e-3)
        self.assertAlmostEqual(row["velocity_exponent_full"], 1.5, delta=2e-3)
        self.assertNotAlmostEqual(row["power_law_exponent"], 1.5, delta=0.3)

    def test_other_exponent_and_broken_balance(self):
        prof = synthetic.bagnold_profiles(14, exponent=1.2)
        prof["stress_yy"] = prof["stress_yy"].copy()
        prof["stress_yy"][3] *= 1.05  # a bulk layer 5 % off the weight above
        row = ib.analyse_run(self.run_of(14, profiles=prof), base_skip=3, surface_skip=8)
        self.assertAlmostEqual(row["velocity_exponent"], 1.2, delta=2e-3)
        self.assertAlmostEqual(row["yy_max_deviation"], 0.05, places=9)
        self.assertLess(row["xy_max_deviation"], 1e-9)

    def test_base_layer_excluded_and_included(self):
        prof = synthetic.bagnold_profiles(12, base_anomaly=0.5)
        self.assertAlmostEqual(
            ib.analyse_run(self.run_of(12, profiles=prof), 3, 8)["s_over_p"], math.tan(math.radians(12)), places=12
        )
        with_base = ib.analyse_run(self.run_of(12, profiles=prof), 0, 8)
        self.assertGreater(with_base["s_over_p"], 1.05 * math.tan(math.radians(12)))
        self.assertGreater(with_base["s_over_p_error"], 0)

    def test_resting_layer(self):
        prof = synthetic.bagnold_profiles(5)
        prof["velocity_x"] = np.zeros_like(prof["y"])
        prof["temperature"] = np.zeros_like(prof["y"])
        prof["inertial"] = np.full_like(prof["y"], np.nan)
        row = ib.analyse_run(self.run_of(5, profiles=prof), 3, 8)
        self.assertEqual(row["flowing"], 0)
        self.assertTrue(math.isnan(row["s_over_p"]) and math.isnan(row["velocity_exponent"]))
        self.assertAlmostEqual(row["packing_fraction"], 0.8)

    def test_too_thin(self):
        with self.assertRaisesRegex(ValueError, "bulk layers"):
            ib.analyse_run(
                self.run_of(12, height_diameters=8, profiles=synthetic.bagnold_profiles(12, height_diameters=8)), 3, 8
            )

    def test_table_round_trip(self):
        paths = []
        for angle in (10, 12):
            paths.append(os.path.join(self.tmp.name, f"t{angle}.h5"))
            synthetic.write_incline_run(paths[-1], angle)
        out = os.path.join(self.tmp.name, "table.h5")
        ib.write_table(out, ib.analyse(paths, 3, 8), 3, 8, "test")
        table = ib.read_table(out)
        np.testing.assert_allclose(table["runs"]["angle"], [10, 12])
        np.testing.assert_allclose(table["bulk"]["s_over_p"], np.tan(np.radians([10, 12])), rtol=1e-12)
        self.assertEqual(list(table["runs"]["input"]), paths)

    def test_times_in_tau_or_code_time_read_alike(self):
        # gf-incline stores its times in τ (unit attributes, /profiles steady_from_time);
        # files of code time (no unit) are divided by τ. Both give the same times in τ.
        parent = os.path.join(self.tmp.name, "parent.h5")
        synthetic.write_incline_run(parent, 12)
        got = {}
        for unit in ("tau", "code"):
            path = os.path.join(self.tmp.name, f"branch_{unit}.h5")
            synthetic.write_incline_run(path, 12, parent=(parent, 0.0, 400.0), steady_from_tau=150.0, time_unit=unit)
            run = ib.read_run(path)["parameters"]
            _, time, _ = ca.read_flow(path)
            got[unit] = (run["start_time"], run["steady_from_tau"], time)
        for unit, (start, steady_from, time) in got.items():
            self.assertAlmostEqual(start, 400.0, places=9, msg=unit)
            self.assertEqual(steady_from, 150.0, unit)
            np.testing.assert_allclose(time, np.arange(1, 4001) * 10 * 5e-3, rtol=1e-12, err_msg=unit)


class CriticalAngleTest(unittest.TestCase):
    def series(self, values):
        time = np.arange(1, len(values) + 1) * 0.05  # τ, one row every 10 steps of 5e-3 τ
        return time, np.asarray(values, dtype=float)

    def test_states(self):
        n = 4000  # 200 τ; the analysed window is the last 100 τ
        t = np.arange(n) * 0.05
        cases = {
            "rest": noise(n, 0.05, 1),
            "steady": 2.0 + noise(n, 0.05, 2),
            "decelerating": 2.0 * np.exp(-t / 40) + noise(n, 0.02, 3),
            "accelerating": 1.0 + 0.01 * t + noise(n, 0.02, 4),
        }
        for expected, values in cases.items():
            with self.subTest(expected):
                self.assertEqual(ca.classify(*self.series(values), 100, 0.02, 0.15)[0], expected)

    def test_creep_counts_as_rest(self):
        # A significant but tiny mean velocity (creep) is rest below --rest-velocity.
        values = 0.005 + noise(4000, 1e-4, 5)
        self.assertEqual(ca.classify(*self.series(values), 100, 0.02, 0.15)[0], "rest")
        self.assertEqual(ca.classify(*self.series(values), 100, 0.001, 0.15)[0], "steady")

    def test_bracket(self):
        self.assertEqual(ca.bracket([4, 6, 8, 10], [0, 0, 1, 1]), (6.0, 8.0, True))
        self.assertEqual(ca.bracket([4, 6, 8, 10], [1, 0, 1, 1]), (6.0, 8.0, False))
        self.assertEqual(ca.bracket([4, 6, 8, 10], [0, 1, 0, 1]), (8.0, 10.0, False))
        self.assertEqual(ca.bracket([4, 6], [0, 0]), (6.0, math.inf, True))
        self.assertEqual(ca.bracket([4, 6], [1, 1]), (-math.inf, 4.0, True))

    def test_sweep_from_files(self):
        with tempfile.TemporaryDirectory() as d:
            n = 4000
            t = np.arange(n) * 0.05
            flows = {
                4: noise(n, 0.05, 1),
                6: 1.5 * np.exp(-t / 60) + noise(n, 0.02, 2),
                8: 0.8 + noise(n, 0.05, 3),
                10: 2.0 + noise(n, 0.05, 4),
            }
            paths = []
            for angle in (10, 4, 8, 6):  # any order
                paths.append(os.path.join(d, f"th{angle}.h5"))
                synthetic.write_incline_run(paths[-1], angle, flow_rate=flows[angle])
            rows, result = ca.analyse(paths, 100, 0.02, 0.15)
            self.assertEqual([r["angle"] for r in rows], [4, 6, 8, 10])
            self.assertEqual([r["state"] for r in rows], ["rest", "decelerating", "steady", "steady"])
            self.assertEqual((result["theta_below"], result["theta_above"]), (6.0, 8.0))
            self.assertAlmostEqual(result["theta_c"], 7.0)
            self.assertAlmostEqual(result["half_width"], 1.0)
            self.assertAlmostEqual(rows[2]["mean_velocity"], 0.8, delta=0.01)
            out = os.path.join(d, "crit.h5")
            res = subprocess.run(
                [
                    sys.executable,
                    os.path.join(PIPELINES, "analysis", "critical_angle.py"),
                    "--window",
                    "100",
                    "-o",
                    out,
                    *paths,
                ],
                capture_output=True,
                text=True,
            )
            self.assertEqual(res.returncode, 0, res.stderr)
            self.assertIn("θ_c in (6°, 8°] = 7° ± 1°", res.stderr)
            self.assertEqual(ca.read_table(out)["critical_angle"]["theta_c"], 7.0)
            # Mixed frictions are two sweeps, not one.
            synthetic.write_incline_run(paths[0], 10, friction=0.4)
            res = subprocess.run(
                [sys.executable, os.path.join(PIPELINES, "analysis", "critical_angle.py"), "-o", out + "2", *paths],
                capture_output=True,
                text=True,
            )
            self.assertEqual(res.returncode, 2)
            self.assertIn("different friction", res.stderr)
            self.assertFalse(os.path.exists(out + "2"))


class InclineOutputsTest(unittest.TestCase, synthetic.ScriptRunner):
    """The Fig 4.7-4.10 scripts and the report section run on synthetic inputs."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = cls.tmp.name
        cls.runs = []
        for angle, mu, nu in ((10, 0.0, 0.82), (12, 0.0, 0.81), (20, 0.4, 0.78)):
            path = os.path.join(d, f"incline_th{angle}_mu{mu}.h5")
            # The μ = 0.4 run is a branch from the end of the 12° one, as at the quick size.
            parent = (cls.runs[1], 0.0, 400.0) if mu else None
            synthetic.write_incline_run(
                path, angle, friction=mu, nu=nu, parent=parent, profiles=synthetic.bagnold_profiles(angle, nu=nu)
            )
            cls.runs.append(path)
        rest = os.path.join(d, "incline_th4.h5")
        synthetic.write_incline_run(rest, 4, flow_rate=noise(4000, 0.05, 7))
        cls.incline_table = os.path.join(d, "ch4_incline.h5")
        ib.write_table(cls.incline_table, ib.analyse(cls.runs, 3, 8), 3, 8, "test")
        cls.critical_table = os.path.join(d, "ch4_critical_angle.h5")
        rows, result = ca.analyse([rest] + cls.runs[:2], 100, 0.02, 0.15)
        ca.write_table(cls.critical_table, rows, result, {"window": 100, "rest_velocity": 0.02, "drift": 0.15}, "test")
        shear = []
        rng = np.random.default_rng(3)
        for mu in (0.0, 0.4):
            for nu in (0.76, 0.80, 0.82):
                scale = 1 / (0.85 - nu) ** 2
                p = scale * (2 + 0.2 * synthetic.ar1(0.8, 600, rng))
                path = os.path.join(d, f"shear_nu{nu}_mu{mu}.h5")
                synthetic.write_run(
                    path,
                    0.9 * p,
                    0.1 * p,
                    0.35 * p,
                    np.full(600, 0.3 * scale),
                    packing_fraction=nu,
                    restitution=0.5,
                    friction=mu,
                    rng=rng,
                )
                shear.append(path)
        cls.sweep_table = os.path.join(d, "ch4_sweep.h5")
        ss.write_table(cls.sweep_table, ss.analyse(shear, 0.1), 0.1, "test")
        cls.packing = synthetic.write_packing(os.path.join(d, "pack.h5"))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_figures(self):
        d = self.tmp.name
        calls = {
            "fig4_7.png": ("plot/ch4_incline_snapshot.py", self.runs[1]),
            "fig4_8.png": ("plot/ch4_incline_profiles.py", self.runs[1]),
            "fig4_9.png": ("plot/ch4_incline_invariants.py", self.runs[1]),
            "fig4_10.png": (
                "plot/ch4_consistent_rheology.py",
                "--restitution",
                "0.5",
                self.incline_table,
                self.sweep_table,
            ),
        }
        for name, command in calls.items():
            out = os.path.join(d, name)
            with self.subTest(figure=name):
                self.run_script(*command, out)
                with open(out, "rb") as fh:
                    self.assertEqual(fh.read(8), b"\x89PNG\r\n\x1a\n")

    def test_report_section(self):
        out = os.path.join(self.tmp.name, "REPORT.md")
        self.run_script(
            "report",
            "--size",
            "test",
            "--output",
            out,
            "--ch4-incline",
            self.incline_table,
            "--ch4-critical",
            self.critical_table,
            self.packing,
        )
        with open(out) as fh:
            text = fh.read()
        for needle in (
            "## Chapter 4: incline flow",
            "(thesis l. 449)",
            "(thesis l. 434)",
            "| 12 | 0 | 1.50 | 1.50 |",
            "θ_c = 7° ± 3°**: the lowest angle of steady flow lies in (4°, 10°].",
            "largest deviation over the bulk layers of all flowing runs 0.00%",
            "| 4 | 0 | ",
            "| rest |",
            "Branched runs (“from” and “run” count from the branch point; velocities kept): θ = 20°, "
            "μ = 0.4 from `incline_th12_mu0.0.h5` (μ = 0) at its 400 τ.",
        ):
            self.assertIn(needle, text)
        # s/p of each flowing run beside tan θ.
        for angle in (10, 12, 20):
            self.assertRegex(text, rf"\| {angle} \| [0.4]+ \| 1 \| .* \({math.tan(math.radians(angle)):.4f}\) \|")

    def test_report_against_shear(self):
        # The shear section needs the ch4 tables; here only the incline-vs-shear interpolation.
        from report import ch4_incline

        sweep = ss.read_table(self.sweep_table)
        got = ch4_incline.interpolate_shear(sweep, 0.0, 0.5, "s_over_p", 0.81)
        self.assertIsNotNone(got)
        self.assertAlmostEqual(got[0], 0.35, delta=0.01)  # s = 0.35 p in every synthetic shear run
        self.assertIsNone(ch4_incline.interpolate_shear(sweep, 0.0, 0.5, "s_over_p", 0.9))


if __name__ == "__main__":
    unittest.main()
