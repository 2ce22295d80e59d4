"""Chapter 5: correlation_table.py reading gf-correlate's ξ_|C| results (computed and tested in
C++: lib/correlation/decay_length, tests/unit/test_correlation_abs.cpp), the sweep-level fit
and rule check on synthetic inputs with known answers, and the figure scripts and the report
section on a synthetic gf-correlate table with known ξ_|C|, flags and ν_bc."""
import glob
import math
import os
import tempfile
import unittest

import numpy as np

from granflow import correlation_table as ct

import synthetic  # a sibling module: the tests' own fixtures

R = (np.arange(300) + 0.5) * 0.07


class RebinTest(unittest.TestCase):
    def test_rebin_keeps_area_integral(self):
        # Fig. 5.2 shows C̄ on gf-correlate's coarse bins, merged here for display only.
        c = np.sin(R)
        rb, cb, _ = ct.rebin(R, c, np.ones_like(R), 5)
        self.assertAlmostEqual(np.sum(cb * rb) * 5, np.sum(c * R), places=9)


class AnisotropyFitTest(unittest.TestCase):
    def test_recovers_parameters_within_errors(self):
        rng = np.random.default_rng(7)
        k = 24
        width = np.pi / k
        theta = (np.arange(k) + 0.5) * width
        misses = 0
        for trial in range(40):
            a0, theta0 = rng.uniform(0.1, 0.8), rng.uniform(-0.5, 0.5)
            damp = np.sin(width) / width
            y = 1 - a0 * damp * np.sin(2 * (theta - theta0)) + 0.03 * rng.normal(size=k)
            fit = ct.fit_anisotropy(theta, y, np.full(k, 0.03), width)
            if abs(fit["a0"] - a0) > 3 * fit["a0_error"] or abs(fit["theta0"] - theta0) > 3 * fit["theta0_error"]:
                misses += 1
        self.assertLessEqual(misses, 2)

    def test_eq53_maximum_on_the_compression_axis(self):
        grid = np.linspace(0, np.pi, 1001)
        self.assertAlmostEqual(grid[np.argmax(ct.eq53(grid, 0.21, 0.0))], 3 * np.pi / 4, places=2)


class PeakRuleTest(unittest.TestCase):
    def test_agreement(self):
        got = ct.peak_agreement([1.0, 1.1, 1.3, 2.0, 1.2, np.nan], [1, 0, 0, 1, 1, 1])
        self.assertEqual(list(got), [True, False, True, False, True, False])


class Ch5OutputsTest(unittest.TestCase, synthetic.ScriptRunner):
    NU_BC = synthetic.CH5_NU_BC
    NOT_MEASURABLE = synthetic.CH5_NOT_MEASURABLE

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        sweep = synthetic.chapter5_tables(cls.tmp.name)
        cls.rows, cls.table, cls.clusters, cls.packing = (sweep[k] for k in ("rows", "table", "clusters", "packing"))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_analysis_reads_the_programs_values(self):
        table = ct.read_table(self.table)
        res = ct.analyse(table)
        runs = table["runs"]
        # Per run: gf-correlate's ξ_|C|, its error, flag and ratio, row by row.
        np.testing.assert_array_equal(res["xi"], [row["xi_abs"] for row in self.rows])
        np.testing.assert_array_equal(res["xi_error"], [0.02] * len(self.rows))
        flagged = {
            (runs["packing_fraction"][i], runs["restitution"][i], runs["friction"][i])
            for i in np.flatnonzero(~res["measurable"])
        }
        self.assertEqual(flagged, self.NOT_MEASURABLE)
        self.assertEqual(res["xi_el"], 1.7)
        self.assertEqual(res["xi_el_error"], 0.012)
        np.testing.assert_allclose(res["ratio"], res["xi"] / 1.7)
        self.assertEqual(list(res["reference_rows"]), [20])
        self.assertEqual((res["factor"], res["k"], res["threshold"], res["max_tail_share"]), (5, 2.0, 1.25, 0.05))
        # Per series: ν_bc and statuses as written, series with no crossing given are all_below.
        series = {(s["restitution"], s["friction"]): s for s in res["series"]}
        self.assertEqual(len(series), 6)
        for key, nu_bc in self.NU_BC.items():
            self.assertEqual(series[key]["status"], "bracketed")
            self.assertAlmostEqual(series[key]["nu_bc"], nu_bc)
            self.assertEqual(series[key]["nu_bc_error"], 0.004)
        self.assertEqual(series[(0.92, 0.0)]["status"], "all_below")
        self.assertEqual(series[(0.0, 0.0)]["runs"], 4)  # ν = 0.81 is not measurable

    def test_table_without_xi_abs_is_refused(self):
        old = os.path.join(self.tmp.name, "old_table.h5")
        import shutil
        import h5py

        shutil.copy(self.table, old)
        with h5py.File(old, "a") as f:
            del f["correlation/xi_abs"]
        with self.assertRaises(SystemExit) as caught:
            ct.analyse(ct.read_table(old))
        self.assertIn("xi_abs", str(caught.exception))
        os.remove(old)

    def test_figures(self):
        d = self.tmp.name
        calls = {
            "fig5_1.png": ("plot/ch5_clusters.py", self.clusters),
            "fig5_2.png": ("plot/ch5_correlation.py", self.table),
            "fig5_3.png": ("plot/ch5_xi.py", "--vary", "restitution", self.table),
            "fig5_4.png": ("plot/ch5_xi.py", "--vary", "friction", "--restitution", "0", self.table),
            "fig5_5.png": ("plot/ch5_anisotropy.py", "--figure", "5.5", self.table),
            "fig5_6.png": ("plot/ch5_anisotropy.py", "--figure", "5.6", self.table),
            "fig5_7.png": ("plot/ch5_forces.py", "--figure", "5.7", self.table),
            "fig5_8.png": ("plot/ch5_forces.py", "--figure", "5.8", self.table),
            "fig5_9.png": ("plot/ch5_phase.py", "--figure", "5.9", self.table),
            "fig5_10.png": ("plot/ch5_phase.py", "--figure", "5.10", self.table),
        }
        for name, command in calls.items():
            out = os.path.join(d, name)
            with self.subTest(figure=name):
                self.run_script(*command, out)
                with open(out, "rb") as fh:
                    self.assertEqual(fh.read(8), b"\x89PNG\r\n\x1a\n")
        self.assertEqual(glob.glob(os.path.join(d, ".*part*")), [])

    def test_report_section(self):
        out = os.path.join(self.tmp.name, "REPORT.md")
        self.run_script(
            "report",
            "--size",
            "test",
            "--output",
            out,
            "--ch5-correlate",
            self.table,
            "--ch5-clusters",
            self.clusters,
            self.packing,
        )
        with open(out) as fh:
            text = fh.read()
        for needle in (
            "## Chapter 5",
            "(thesis l. 555)",
            "(thesis l. 645)",
            "| 0.770 |",
            "all_below",
            "a0 = ",
            "| `window1.h5` | 2 | 13 | 2 | 10 |",
            "| 0 | 0 | 4 | 0.6917 ± 0.0040 | bracketed |",
            "| 0.25 | 0 | 5 | 0.7417 ± 0.0040 | bracketed |",
            "1.459 ± 0.016 † ○",
            "decay length per direction",
            "pooled fit of eq. 5.3's shape): a0 = 0.100",
        ):
            self.assertIn(needle, text)
        # The synthetic P(f) decisions follow the rule exactly.
        self.assertRegex(
            text,
            r"of the (\d+) runs with ξ/ξ_el ≥ 1.25, \1 have their maximum at f = 0; "
            r"of the (\d+) runs with ξ/ξ_el < 1.25, \2 have a peak",
        )


if __name__ == "__main__":
    unittest.main()
