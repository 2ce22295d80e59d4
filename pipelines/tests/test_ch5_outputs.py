"""Chapter 5: the pipeline-level analysis (correlation_table.py) on synthetic inputs with known
answers, and smoke tests of the figure scripts and the report section on a synthetic
gf-correlate table."""
import glob
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
PIPELINES = os.path.join(HERE, "..")
sys.path.insert(0, os.path.join(PIPELINES, "analysis"))
sys.path.insert(0, HERE)
import correlation_table as ct  # noqa: E402
import synthetic  # noqa: E402

R = (np.arange(300) + 0.5) * 0.07


class MagnitudeLengthTest(unittest.TestCase):
    def test_exponential_envelope(self):
        # |C̄| = A e^{-(ℓ-d)/ξ} beyond d: ∫ℓ|C̄|/∫|C̄| = d + ξ (exactly, for an untruncated tail).
        for xi in (0.5, 1.5, 3.0):
            for oscillation in (None, 2.0):
                c, err = synthetic.correlation_row(R, xi, oscillation=oscillation)
                got, got_err = ct.xi_magnitude(R, c, err, k=0.0, factor=1)
                expected = 1.4 + xi
                if oscillation:  # |cos| averages the envelope: only approximately d + ξ
                    self.assertAlmostEqual(got, expected, delta=0.1 * expected)
                else:
                    self.assertAlmostEqual(got, expected, delta=0.01 * expected)

    def test_noise_floor_is_removed(self):
        rng = np.random.default_rng(1)
        c, err = synthetic.correlation_row(R, 1.0, amplitude=0.05, noise=1e-3, rng=rng)
        raw, _ = ct.xi_magnitude(R, c, err, k=0.0, factor=5)
        clean, _ = ct.xi_magnitude(R, c, err, k=2.0, factor=5)
        # Without thresholding, the ℓ-weighted noise floor drags ξ out (+35 % here); with it,
        # ξ ≈ d + ξ, biased low by the part of the tail hidden in the noise (−7 % here).
        self.assertGreater(raw, 1.2 * 2.4)
        self.assertAlmostEqual(clean, 2.4, delta=0.2)

    def test_dilute_limit_is_mean_contact_distance(self):
        # Binary collisions: C̄ < 0 only at contact distances 1.3 and 1.5 with weights 1 : 3.
        c = np.zeros_like(R)
        c[np.argmin(np.abs(R - 1.3))] = -1.0 / 1.3
        c[np.argmin(np.abs(R - 1.5))] = -3.0 / 1.5
        got, _ = ct.xi_magnitude(R, c, np.full_like(R, 1e-9), k=2.0, factor=1)
        # Weights ∝ |C̄|·(bin area ∝ ℓ) · ... : the |C̄|-weighted mean of the two distances.
        w1, w2 = 1.0 / 1.3, 3.0 / 1.5
        self.assertAlmostEqual(got, (R[np.argmin(np.abs(R - 1.3))] * w1 + R[np.argmin(np.abs(R - 1.5))] * w2)
                               / (w1 + w2), places=9)

    def test_tail_share_flags_box_spanning_correlations(self):
        c, err = synthetic.correlation_row(R, 1.0, noise=1e-4, rng=np.random.default_rng(2))
        self.assertLess(ct.tail_share(R, c, err), 0.01)
        # A network spanning the cell: a plateau of −5e-4 up to ℓ_max besides the contact peak.
        plateau = c - np.where(R > 1.4, 5e-4, 0.0)
        self.assertGreater(ct.tail_share(R, plateau, err), 0.05)

    def test_rebin_keeps_area_integral(self):
        c = np.sin(R)
        rb, cb, _ = ct.rebin(R, c, np.ones_like(R), 5)
        self.assertAlmostEqual(np.sum(cb * rb) * 5, np.sum(c * R), places=9)


class CrossingTest(unittest.TestCase):
    def test_linear_interpolation_and_error(self):
        nu = np.array([0.5, 0.6, 0.7, 0.8])
        xi = np.array([1.0, 1.1, 1.3, 2.0])
        got = ct.crossing(nu, xi, np.full(4, 0.01), 1.0, 0.0, 1.25)
        self.assertEqual(got["status"], "bracketed")
        self.assertAlmostEqual(got["nu_bc"], 0.6 + 0.15 / 0.2 * 0.1)
        # Error: |∂ν/∂ξ1|·0.01 and |∂ν/∂ξ2|·0.01 in quadrature.
        d1, d2 = 0.1 * 0.05 / 0.04, 0.1 * 0.15 / 0.04
        self.assertAlmostEqual(got["nu_bc_error"], 0.01 * math.hypot(d1, d2))

    def test_statuses(self):
        nu = np.array([0.5, 0.6, 0.7])
        self.assertEqual(ct.crossing(nu, [1.0, 1.1, 1.2], [0.01] * 3, 1.0, 0.0)["status"], "all_below")
        self.assertEqual(ct.crossing(nu, [1.3, 1.4, 1.5], [0.01] * 3, 1.0, 0.0)["status"], "all_above")
        self.assertEqual(ct.crossing(nu, [1.3, 1.1, 1.0], [0.01] * 3, 1.0, 0.0)["status"], "only_downward")
        self.assertEqual(ct.crossing([0.5], [1.0], [0.01], 1.0, 0.0)["status"], "too_few")

    def test_runs_at_the_same_nu_are_merged(self):
        got = ct.crossing([0.5, 0.5, 0.7], [1.0, 1.2, 1.5], [0.01] * 3, 1.0, 0.0)
        self.assertAlmostEqual(got["nu_bc"], 0.5 + 0.15 / 0.4 * 0.2)


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


class Ch5OutputsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = cls.tmp.name
        rng = np.random.default_rng(11)
        rows = []
        for mu in (0.0, 0.4):
            for e in ((0.0, 0.25, 0.5, 0.75, 0.92) if mu == 0 else (0.0,)):
                for nu in (0.3, 0.6, 0.7, 0.77, 0.81):
                    # ξ_|C| grows with ν and with decreasing e; dilute: ξ_el ≈ d + 0.3.
                    xi = 0.3 + 3.0 * max(0.0, nu - 0.55 - 0.2 * e) + (0.5 if mu > 0 and nu > 0.7 else 0)
                    c, err = synthetic.correlation_row(R, xi, noise=1e-4, rng=rng)
                    dense = 1.4 + xi > 1.25 * 1.74  # ξ_el comes out 1.74 (bins)
                    rows.append(dict(input=os.path.join(d, f"shear_nu{nu:.3f}_e{e:.2f}_mu{mu:.2f}.h5"),
                                     packing_fraction=nu, restitution=e, friction=mu, C=c, C_error=err,
                                     xi=1.4 + xi, xi_error=0.05, peak=0 if dense else 1,
                                     force_mode=0.0 if dense else 0.8))
        ref = rows[4 * 5 + 0]["input"]  # e = 0.92, ν = 0.3
        cls.table = synthetic.write_correlate_table(os.path.join(d, "ch5_correlate.h5"), rows, reference=[ref])
        runs = [synthetic.write_packing(os.path.join(d, f"window{k}.h5")) for k in range(2)]
        labels = [np.array([0, 1, 1, 2, 2, 3, 3, 0, 0, 4, 4, 0, 5, 5, 0, 0]),
                  np.array([1] * 10 + [2, 2, 2, 0, 0, 0])]
        cls.clusters = synthetic.write_clusters_table(os.path.join(d, "ch5_clusters.h5"), runs, labels)
        cls.packing = synthetic.write_packing(os.path.join(d, "pack.h5"))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def run_script(self, script, *args):
        res = subprocess.run([sys.executable, os.path.join(PIPELINES, script), *args], capture_output=True, text=True)
        self.assertEqual(res.returncode, 0, res.stderr)
        return res

    def test_analysis_of_the_sweep(self):
        res = ct.analyse(ct.read_table(self.table))
        # Dilute rows: contact distance 1.4 plus a 0.3 tail (+0.04 from the bins' discretisation).
        self.assertAlmostEqual(res["xi_el"], 1.7, delta=0.05)
        series = {(s["restitution"], s["friction"]): s for s in res["series"]}
        # ξ_|C| = 1.4 + 0.3 + 3(ν − 0.55 − 0.2e)+ crosses 1.25·1.7 at ν = 0.6917 + 0.2e.
        for e in (0.0, 0.25, 0.5):
            s = series[(e, 0.0)]
            self.assertEqual(s["status"], "bracketed")
            self.assertAlmostEqual(s["nu_bc"], 0.6917 + 0.2 * e, delta=0.03)
            self.assertLess(s["nu_below"], s["nu_bc"])
            self.assertGreater(s["nu_above"], s["nu_bc"])
        self.assertLess(series[(0.0, 0.4)]["nu_bc"], series[(0.0, 0.0)]["nu_bc"])
        self.assertEqual(series[(0.92, 0.0)]["status"], "all_below")

    def test_figures(self):
        d = self.tmp.name
        calls = {"fig5_1.png": ("plot/ch5_clusters.py", self.clusters),
                 "fig5_2.png": ("plot/ch5_correlation.py", self.table),
                 "fig5_3.png": ("plot/ch5_xi.py", "--vary", "restitution", self.table),
                 "fig5_4.png": ("plot/ch5_xi.py", "--vary", "friction", "--restitution", "0", self.table),
                 "fig5_5.png": ("plot/ch5_anisotropy.py", "--figure", "5.5", self.table),
                 "fig5_6.png": ("plot/ch5_anisotropy.py", "--figure", "5.6", self.table),
                 "fig5_7.png": ("plot/ch5_forces.py", "--figure", "5.7", self.table),
                 "fig5_8.png": ("plot/ch5_forces.py", "--figure", "5.8", self.table),
                 "fig5_9.png": ("plot/ch5_phase.py", "--figure", "5.9", self.table),
                 "fig5_10.png": ("plot/ch5_phase.py", "--figure", "5.10", self.table)}
        for name, command in calls.items():
            out = os.path.join(d, name)
            with self.subTest(figure=name):
                self.run_script(*command, out)
                with open(out, "rb") as fh:
                    self.assertEqual(fh.read(8), b"\x89PNG\r\n\x1a\n")
        self.assertEqual(glob.glob(os.path.join(d, ".*part*")), [])

    def test_report_section(self):
        out = os.path.join(self.tmp.name, "REPORT.md")
        self.run_script("report.py", "--size", "test", "--output", out, "--ch5-correlate", self.table,
                        "--ch5-clusters", self.clusters, self.packing)
        with open(out) as fh:
            text = fh.read()
        for needle in ("## Chapter 5", "(thesis l. 555)", "(thesis l. 645)", "| 0.770 |", "all_below",
                       "a0 = ", "| `window1.h5` | 2 | 13 | 2 | 10 |"):
            self.assertIn(needle, text)
        # The synthetic P(f) decisions follow the rule exactly.
        self.assertRegex(text, r"of the (\d+) runs with ξ/ξ_el ≥ 1.25, \1 have their maximum at f = 0; "
                               r"of the (\d+) runs with ξ/ξ_el < 1.25, \2 have a peak")


if __name__ == "__main__":
    unittest.main()
