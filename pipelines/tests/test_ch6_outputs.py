"""Chapter 6: kinetic_table.py's comparisons across ν on constructed inputs with known answers,
and the figure script and the report section on a synthetic gf-kinetic table (the layout of
docs/file-format.md) and gf-correlate table whose binary-collision ranges, Enskog-pressure
ranges, ξ/ξ_el colouring and velocity correlations are chosen by the test (synthetic.py)."""
import glob
import os
import re
import subprocess
import sys
import tempfile
import unittest

import numpy as np

from granflow import correlation_table as ct
from granflow import kinetic_table as kt

import synthetic  # a sibling module: the tests' own fixtures

NAN = float("nan")


class FilledRuleTest(unittest.TestCase):
    def test_threshold_is_strict_and_nan_is_open(self):
        got = kt.filled([1.0, 1.25, 1.2501, 3.0, NAN])
        self.assertEqual(list(got), [False, False, True, True, False])

    def test_not_measurable_is_filled(self):
        # Correlations that reach the box: ξ is at least the cell's, beyond the dilute regime.
        got = kt.filled([1.0, 1.0, NAN], measurable=[True, False, False])
        self.assertEqual(list(got), [False, True, False])


class DiluteRangeTest(unittest.TestCase):
    def test_contiguous_from_the_dilute_end(self):
        nu = [0.7, 0.3, 0.5, 0.6, 0.8]  # any order
        ok = [False, True, True, True, True]
        self.assertEqual(kt.dilute_range(nu, ok), (0.6, [0.8]))

    def test_fails_at_the_dilute_end(self):
        upto, again = kt.dilute_range([0.3, 0.5, 0.6], [False, True, True])
        self.assertTrue(np.isnan(upto))
        self.assertEqual(again, [0.5, 0.6])

    def test_holds_everywhere(self):
        self.assertEqual(kt.dilute_range([0.3, 0.5], [True, True]), (0.5, []))

    def test_agree_within_errors_and_nan(self):
        got = kt.agree([1.0, 1.0, 1.0, NAN], [0.1] * 4, [1.28, 1.29, 1.0, 1.0], [0.1] * 4)
        # 2 combined errors = 0.2828...
        self.assertEqual(list(got), [True, False, True, False])


class WordsTest(unittest.TestCase):
    def test_sign_against_baseline(self):
        self.assertEqual(kt.sign_word(-0.2, 0.01, -0.25), "positive")
        self.assertEqual(kt.sign_word(-0.3, 0.01, -0.25), "negative")
        self.assertEqual(kt.sign_word(-0.24, 0.01, -0.25), "zero within errors")
        self.assertEqual(kt.sign_word(NAN, 0.01, -0.25), "not measured")

    def test_closer_prediction(self):
        self.assertEqual(kt.closer_prediction(1 / 2.1, 1.05), "2D Garzó–Dufty")
        self.assertEqual(kt.closer_prediction(0.98, 0.45), "eq. 6.10 as printed")
        self.assertEqual(kt.closer_prediction(NAN, NAN), "not measured")

    def test_proportionality(self):
        r, n = kt.proportionality([0.1, 0.2, 0.3, NAN], [0.4, 0.8, 1.2, 5.0])
        self.assertAlmostEqual(r, 1.0)
        self.assertEqual(n, 3)
        self.assertTrue(np.isnan(kt.proportionality([0.1, 0.2], [1, 2])[0]))


class Ch6OutputsTest(unittest.TestCase, synthetic.ScriptRunner):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        sweep = synthetic.chapter6_tables(cls.tmp.name)
        cls.kinetic, cls.correlate, cls.packing = sweep["kinetic"], sweep["correlate"], sweep["packing"]
        out = os.path.join(cls.tmp.name, "REPORT.md")
        pipelines = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
        res = subprocess.run(
            [sys.executable, os.path.join(pipelines, "report"), "--size", "test", "--output", out,
             "--ch5-correlate", cls.correlate, "--ch6-kinetic", cls.kinetic, cls.packing],
            capture_output=True, text=True,
        )
        cls.report = f"the report failed:\n{res.stderr}"
        if res.returncode == 0:
            with open(out) as fh:
                cls.report = fh.read()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_xi_ratio_matched_by_path(self):
        table = kt.read_table(self.kinetic)
        ratio, _, measurable = kt.xi_ratio(table, ct.read_table(self.correlate))
        nu = kt.column(table, "packing_fraction")
        np.testing.assert_allclose(ratio, np.where(nu >= synthetic.CH6_FILLED_FROM - 1e-9, 1.5, 1.1))
        self.assertTrue(measurable.all())
        np.testing.assert_array_equal(kt.filled(ratio, measurable), nu >= synthetic.CH6_FILLED_FROM - 1e-9)

    def test_figures(self):
        for k, pair in enumerate((("0.92", "0.75"), ("0.5", "0.25"), ("0.1", "0")), start=1):
            out = os.path.join(self.tmp.name, f"fig6_{k}.png")
            with self.subTest(figure=k):
                self.run_script("plot/ch6_kinetic.py", "--restitutions", *pair, self.kinetic, self.correlate, out)
                with open(out, "rb") as fh:
                    self.assertEqual(fh.read(8), b"\x89PNG\r\n\x1a\n")
        self.assertEqual(glob.glob(os.path.join(self.tmp.name, ".*part*")), [])

    def row_of(self, e):
        match = re.search(rf"^\| {e:g} \| 5 \| (.*)$", self.report, re.M)
        self.assertIsNotNone(match, f"no row for e = {e:g} in\n{self.report}")
        return [c.strip() for c in match.group(1).rstrip("|").split("|")]

    def test_binary_collision_and_pressure_ranges(self):
        self.assertIn("## Chapter 6", self.report)
        for needle in ("(thesis l. 739)", "(thesis l. 798)", "(thesis l. 800)", "(thesis l. 806)"):
            self.assertIn(needle, self.report)
        for e, upto in synthetic.CH6_AGREE_UPTO.items():
            with self.subTest(e=e):
                cells = self.row_of(e)
                expected = f"0.300–{upto:.3f}" if upto is not None else "none (differ at the most dilute ν)"
                self.assertEqual(cells[0], expected)
                again = synthetic.CH6_AGREE_AGAIN.get(e)
                self.assertEqual(cells[1], ", ".join(f"{v:.3f}" for v in again) if again else "–")
                pupto = synthetic.CH6_PRESSURE_UPTO[e]
                self.assertEqual(cells[2], f"{pupto:.3f}" if pupto is not None else "none")
                self.assertEqual(cells[3], "1.020" if pupto is not None else "1.080")
                self.assertEqual(cells[4], "0.600")  # ξ/ξ_el ≤ 1.25 below ν = 0.7

    def test_dilute_shear_stress_prediction(self):
        self.assertIn(
            "s^s/s_pred = 0.477 for eq. 6.10 as printed, 1.050 for the 2D Garzó–Dufty viscosity", self.report
        )
        self.assertIn("the data follow **2D Garzó–Dufty** more closely", self.report)

    def test_velocity_correlation_beside_shear_error(self):
        # Open points: ν < 0.7, three per e; e = 0.1 has no C_v.
        for e, excess in synthetic.CH6_CV_EXCESS.items():
            with self.subTest(e=e):
                rows = re.findall(rf"^\| {e:g} \| 0\.[356]00 \| (.*)$", self.report, re.M)
                self.assertEqual(len(rows), 3, self.report)
                for row in rows:
                    cells = [c.strip() for c in row.rstrip("|").split("|")]
                    if np.isnan(excess):
                        self.assertEqual(cells[0], "not measured")
                        self.assertEqual(cells[2], "not measured")
                    else:
                        self.assertEqual(cells[2], "positive")
                        self.assertEqual(cells[3], "negative")  # C_v itself is below 0
        self.assertIn(
            "Over the 18 open points: C_v − baseline is positive in 15, negative in 0, zero within errors in 0, "
            "not measured in 3.",
            self.report,
        )
        # Pearson's r over the constructed open points: relative error of eq. 6.10 = 4 (C_v − baseline)
        # except at the dilute e = 0.92 point, where s^s = 1.05 s_2D = (1.05/2.2) s_6.10.
        excess, error = [], []
        for e, x in synthetic.CH6_CV_EXCESS.items():
            if np.isnan(x):
                continue
            for nu in (0.3, 0.5, 0.6):
                excess.append(x)
                error.append(2.2 / 1.05 - 1 if (e == 0.92 and nu == 0.3) else 4 * x)
        expected = np.corrcoef(excess, error)[0, 1]
        got = re.search(r"Pearson's r [^:]*: (\S+) for eq\. 6\.10 as printed \((\d+) points\)", self.report)
        self.assertEqual((got.group(1), got.group(2)), (f"{expected:.3f}", "15"))

    def test_nan_safe(self):
        # A table where the stresses are NaN: the report says "not measured" instead of failing.
        d = self.tmp.name
        rows = [
            dict(input=os.path.join(d, f"shear_nu{nu:.3f}_e0.92_mu0.00_r1e-02_s1.h5"), packing_fraction=nu,
                 restitution=0.92, friction=0.0, rate=0.01, p0=1.0, eta0=1.0)
            for nu in (0.3, 0.5)
        ]
        kinetic = synthetic.write_kinetic_table(os.path.join(d, "nan_kinetic.h5"), rows)
        out = os.path.join(d, "NAN_REPORT.md")
        self.run_script(
            "report", "--size", "test", "--output", out, "--ch5-correlate", self.correlate,
            "--ch6-kinetic", kinetic, self.packing,
        )
        with open(out) as fh:
            text = fh.read()
        self.assertIn("| 0.92 | 2 | none (differ at the most dilute ν) | – | none | not measured | 0.500 |", text)
        self.assertIn("s^s/s_pred = not measured for eq. 6.10 as printed, not measured", text)
        self.assertIn("zero within errors in 0, not measured in 2. Pearson's r", text)
        self.assertIn("not measured for eq. 6.10 as printed (0 points)", text)
        self.run_script("plot/ch6_kinetic.py", "--restitutions", "0.92", "0.75", kinetic, self.correlate,
                        os.path.join(d, "nan.png"))


if __name__ == "__main__":
    unittest.main()
