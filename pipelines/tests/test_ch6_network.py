"""Chapter 6, the force-network model: network_table.py's reader and sweep statistics (Fig. 6.8's
collapse, Ψ < Φ, the 4θ components, z at two steps, the identity s^bc/p^bc = −2χ12) on
constructed inputs with known answers, and the figure script and report section on synthetic
gf-network tables laid out as the issue-22 contract says (synthetic.write_network_table)."""
import glob
import math
import os
import re
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

from granflow import network_table as nt

import synthetic  # a sibling module: the tests' own fixtures

NAN = float("nan")
# The synthetic sweep: rows in this order (e, ν).
GRID = [(0.0, 0.7), (0.0, 0.79), (0.0, 0.81), (0.5, 0.7), (0.5, 0.79), (0.5, 0.81)]
RHS = np.array([1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3])  # five decades
PHI = [0.80, 0.81, 0.82, 0.83, 0.84, 0.85]
PSI = [0.30, 0.40, 0.50, 0.60, 0.70, 0.90]  # Ψ ≥ Φ in the last row only
A4_C = [0.001, -0.002, -0.012, 0.003, 0.0, 0.004]  # one component ≥ 0.01
A4_F = [0.005, 0.001, -0.002, 0.0, 0.001, 0.003]


def sweep_rows(d):
    """Six runs with known answers: lhs_pressure = rhs_pressure (slope 1, scatter 0), the floor
    reading 10^0.1 below it (slope 1, scatter 0.1 dex), the active reading its square (slope
    0.5), lhs_shear ≤ 0 in one row, rhs_xx NaN in one row; s^bc/p^bc = −2χ12 except +3σ in row 4."""
    rows = []
    for k, (e, nu) in enumerate(GRID):
        rows.append(
            dict(
                input=os.path.join(d, f"shear_nu{nu:.3f}_e{e:.2f}_mu0.00_r1e-02_s1.h5"),
                packing_fraction=nu,
                restitution=e,
                friction=0.0,
                tangential_restitution=0.0,
                rate=0.01,
                dt=0.1,
                coordination=3.0 + k * 0.1,
                coordination_error=0.05,
                Phi=PHI[k],
                Phi_error=0.01,
                Psi=PSI[k],
                Psi_error=0.01,
                a_c=-0.2 + 0.01 * k,
                a_c_error=0.01,
                a_c_prime=-0.05,
                a_c_prime_error=0.01,
                a_f=-0.3,
                a_f_error=0.01,
                a_f_prime=0.05 + 0.01 * k,
                a_f_prime_error=0.01,
                a4_c=A4_C[k],
                a4_c_error=0.001,
                a4_c_prime=0.0,
                a4_c_prime_error=0.001,
                a4_f=A4_F[k],
                a4_f_error=0.001,
                a4_f_prime=0.0,
                a4_f_prime_error=0.001,
                chi_12=-0.1,
                chi_12_error=0.01,
                shear_ratio_collisional=0.2 + (0.06 if k == 4 else 0.0),
                shear_ratio_collisional_error=0.0,
                shear_ratio_collisional_frames=0.2,
                shear_ratio_collisional_frames_error=0.0,
                sigma_anisotropy=0.001 * (k + 1),
                sigma_max_deviation=0.01 * (k + 1),
                lhs_pressure=RHS[k],
                lhs_pressure_error=0.1,
                xi_ratio_error=0.2,
                rhs_pressure=RHS[k],
                rhs_pressure_floor=RHS[k] / 10**0.1,
                rhs_pressure_active=RHS[k] ** 2,
                rhs_pressure_unit=RHS[k],
                lhs_shear=-0.5 if k == 2 else RHS[k],
                rhs_shear=RHS[k],
                rhs_shear_floor=RHS[k],
                rhs_shear_active=RHS[k],
                rhs_shear_unit=RHS[k],
                lhs_xx=RHS[k],
                rhs_xx=NAN if k == 0 else RHS[k],
                rhs_xx_floor=RHS[k],
                rhs_xx_active=RHS[k],
                rhs_xx_unit=RHS[k],
                continuation_real=0 if k == 5 else 1,
                sum_limit=2.5,
            )
        )
    return rows


def halfstep_rows(d):
    """Pairs (default, half step) at ν = 0.7 (z 4.0, 4.3 ± 0.1: +2.1σ) and 0.79 (equal), e = 0,
    and an unpaired run at ν = 0.81."""
    rows = []
    for nu, dt, z in ((0.7, 0.1, 4.0), (0.7, 0.05, 4.3), (0.79, 0.1, 3.0), (0.79, 0.05, 3.0), (0.81, 0.1, 5.0)):
        name = "halfstep" if dt == 0.05 else "shear"
        rows.append(
            dict(
                input=os.path.join(d, f"{name}_nu{nu:.3f}_e0.00_mu0.00_r1e-02_s1.h5"),
                packing_fraction=nu,
                restitution=0.0,
                friction=0.0,
                tangential_restitution=0.0,
                rate=0.01,
                dt=dt,
                coordination=z,
                coordination_error=0.1,
                Phi=0.83,
                Psi=0.5,
            )
        )
    return rows


class CollapseTest(unittest.TestCase):
    def test_power_law_slope_and_scatter(self):
        rhs = np.logspace(-2, 2, 9)
        lhs = 3.0 * rhs**1.5
        c = nt.collapse(lhs, rhs)
        self.assertAlmostEqual(c["slope"], 1.5)
        self.assertAlmostEqual(c["intercept"], math.log10(3.0))
        expected = np.sqrt(np.mean((math.log10(3.0) + 0.5 * np.log10(rhs)) ** 2))
        self.assertAlmostEqual(c["scatter"], expected)
        self.assertAlmostEqual(c["decades_rhs"], 4.0)
        self.assertAlmostEqual(c["decades_lhs"], 6.0)
        self.assertEqual((c["used"], c["non_positive"], c["missing"]), (9, 0, 0))

    def test_offset_is_scatter_and_bad_rows_counted(self):
        rhs = [1e-3, 1e-1, 1e1, 1e3, 2.0, 5.0, -1.0, NAN, 1.0]
        lhs = [10**0.2 * 1e-3, 10**-0.2 * 1e-1, 10**0.2 * 1e1, 10**-0.2 * 1e3, 0.0, -3.0, 1.0, 1.0, NAN]
        c = nt.collapse(lhs, rhs)
        self.assertEqual((c["used"], c["non_positive"], c["missing"]), (4, 3, 2))
        self.assertAlmostEqual(c["scatter"], 0.2)
        self.assertAlmostEqual(c["decades_rhs"], 6.0)

    def test_too_few_rows(self):
        c = nt.collapse([1.0], [2.0])
        self.assertTrue(math.isnan(c["slope"]))
        self.assertAlmostEqual(c["scatter"], math.log10(2.0))
        c = nt.collapse([-1.0, NAN], [1.0, 1.0])
        self.assertEqual((c["used"], c["non_positive"], c["missing"]), (0, 1, 1))
        self.assertTrue(math.isnan(c["scatter"]))


class NetworkTableTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.path = synthetic.write_network_table(os.path.join(cls.tmp.name, "net.h5"), sweep_rows(cls.tmp.name))
        cls.half = synthetic.write_network_table(
            os.path.join(cls.tmp.name, "half.h5"), halfstep_rows(cls.tmp.name), xi_source="none"
        )
        cls.table = nt.read_table(cls.path)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_reader_and_selection(self):
        self.assertEqual(nt.rows(self.table), 6)
        self.assertEqual(nt.restitutions(self.table), [0.5, 0.0])
        np.testing.assert_array_equal(nt.select(self.table, 0.5), [3, 4, 5])
        self.assertEqual(nt.nearest(self.table, 0.0, 0.79), 1)
        self.assertEqual(nt.nearest(self.table, 0.1, 0.8), 1)  # nearest e first, then ν
        self.assertEqual(self.table["histograms"]["C"].shape, (6, 36))
        self.assertTrue(np.isnan(nt.column(self.table, "no_such_dataset")).all())

    def test_collapse_per_reading(self):
        got = {(c["equation"], c["reading"]): c for c in nt.collapse_table(self.table)}
        self.assertEqual(len(got), 12)
        main, floor, active = got[("pressure", "")], got[("pressure", "_floor")], got[("pressure", "_active")]
        self.assertAlmostEqual(main["slope"], 1.0)
        self.assertAlmostEqual(main["scatter"], 0.0)
        self.assertAlmostEqual(main["decades_rhs"], 5.0)
        self.assertAlmostEqual(floor["slope"], 1.0)
        self.assertAlmostEqual(floor["scatter"], 0.1)
        self.assertAlmostEqual(active["slope"], 0.5)
        self.assertEqual((got[("shear", "")]["used"], got[("shear", "")]["non_positive"]), (5, 1))
        self.assertEqual((got[("xx", "")]["used"], got[("xx", "")]["missing"]), (5, 1))

    def test_phi_psi_and_next_order(self):
        below, finite, exceptions = nt.psi_below_phi(self.table)
        self.assertEqual((below, finite, list(exceptions)), (5, 6, [5]))
        value, error, name, row = nt.largest_abs(self.table, ("a4_c", "a4_c_prime"))
        self.assertEqual((value, error, name, row), (-0.012, 0.001, "a4_c", 2))
        self.assertEqual(nt.count_at_least(self.table, ("a4_c", "a4_c_prime"), 0.01), (1, 6))
        self.assertEqual(nt.count_at_least(self.table, ("a4_f", "a4_f_prime"), 0.01), (0, 6))

    def test_identity(self):
        ratio, _, target, target_error, sig = nt.identity_deviation(self.table)
        np.testing.assert_allclose(target, 0.2)
        np.testing.assert_allclose(target_error, 0.02)
        np.testing.assert_allclose(sig, [0, 0, 0, 0, 3.0, 0], atol=1e-12)
        self.assertEqual(nt.largest_finite(sig), 4)

    def test_bound_excess(self):
        # lhs_pressure 10^-2 … 10^3 against ξ/ξ_el − 1 = 2.5, errors 0.1 and 0.2 combined.
        sig = nt.bound_excess(self.table)
        np.testing.assert_allclose(sig, (RHS - 2.5) / np.hypot(0.1, 0.2))
        self.assertEqual(int(np.sum(sig > nt.AGREE_SIGMAS)), 3)

    def test_step_pairs(self):
        half = nt.read_table(self.half)
        self.assertEqual(nt.step_pairs(half), [(0, 1), (2, 3)])
        self.assertEqual(nt.step_pairs(self.table), [])
        self.assertEqual(half["prediction"]["attrs"]["xi_source"], "none")

    def test_not_a_network_table(self):
        path = os.path.join(self.tmp.name, "other.h5")
        with h5py.File(path, "w") as f:
            f.create_group("runs")
        with self.assertRaises(SystemExit) as cm:
            nt.read_table(path)
        self.assertIn("not a gf-network table", str(cm.exception))
        with self.assertRaises(SystemExit):
            nt.read_table(os.path.join(self.tmp.name, "missing.h5"))


class Ch6NetworkOutputsTest(unittest.TestCase, synthetic.ScriptRunner):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = cls.tmp.name
        cls.network = synthetic.write_network_table(os.path.join(d, "ch6_network.h5"), sweep_rows(d))
        cls.half = synthetic.write_network_table(os.path.join(d, "half.h5"), halfstep_rows(d), xi_source="none")
        cls.packing = synthetic.write_packing(os.path.join(d, "pack.h5"))
        out = os.path.join(d, "REPORT.md")
        pipelines = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
        res = subprocess.run(
            [
                sys.executable,
                os.path.join(pipelines, "report"),
                "--size",
                "test",
                "--output",
                out,
                "--ch6-network",
                cls.network,
                "--ch6-network-halfstep",
                cls.half,
                cls.packing,
            ],
            capture_output=True,
            text=True,
        )
        cls.report = f"the report failed:\n{res.stderr}"
        if res.returncode == 0:
            with open(out) as fh:
                cls.report = fh.read()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_figures(self):
        for figure in ("6.5", "6.6", "6.7", "6.8"):
            out = os.path.join(self.tmp.name, f"fig{figure.replace('.', '_')}.png")
            with self.subTest(figure=figure):
                self.run_script("plot/ch6_network.py", "--figure", figure, "--halfstep", self.half, self.network, out)
                with open(out, "rb") as fh:
                    self.assertEqual(fh.read(8), b"\x89PNG\r\n\x1a\n")
        # Without the half-step table, and a table without ξ/ξ_el (every rhs NaN): still drawn.
        out = os.path.join(self.tmp.name, "fig6_7_alone.png")
        self.run_script("plot/ch6_network.py", "--figure", "6.7", self.network, out)
        out = os.path.join(self.tmp.name, "fig6_8_no_xi.png")
        self.run_script("plot/ch6_network.py", "--figure", "6.8", self.half, out)
        # F_bc(θ) not measured (NaN: a θ bin without contacts has no mean force, and gf-network's
        # normalisation by the bin average spreads that NaN to every bin) nor its components.
        gaps = os.path.join(self.tmp.name, "gaps.h5")
        rows = halfstep_rows(self.tmp.name)
        synthetic.write_network_table(gaps, rows, xi_source="none")
        with h5py.File(gaps, "r+") as f:
            f["/histograms/binary_force"][0, :] = NAN
            f["/runs/a_f"][0] = NAN
        self.run_script(
            "plot/ch6_network.py",
            "--figure",
            "6.5",
            "--nu",
            "0.7",
            gaps,
            os.path.join(self.tmp.name, "fig6_5_gaps.png"),
        )
        self.assertEqual(glob.glob(os.path.join(self.tmp.name, ".*part*")), [])

    def test_figure_refuses_another_table(self):
        path = os.path.join(self.tmp.name, "kinetic.h5")
        synthetic.write_kinetic_table(path, [dict(input="a.h5", packing_fraction=0.5)])
        out = os.path.join(self.tmp.name, "never.png")
        pipelines = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
        res = subprocess.run(
            [sys.executable, os.path.join(pipelines, "plot/ch6_network.py"), "--figure", "6.8", path, out],
            capture_output=True,
            text=True,
        )
        self.assertNotEqual(res.returncode, 0)
        self.assertIn("not a gf-network table", res.stderr)
        self.assertEqual(len(res.stderr.strip().splitlines()), 1, res.stderr)
        self.assertFalse(os.path.exists(out))

    def test_phi_and_psi(self):
        self.assertIn("## Chapter 6: the force-network model", self.report)
        for needle in ("(thesis l. 953)", "(thesis l. 955)", "(thesis l. 910)", "(thesis l. 957)"):
            self.assertIn(needle, self.report)
        self.assertIn(
            "Φ from 0.800 ± 0.010 (ν = 0.700, e = 0) to 0.850 ± 0.010 (ν = 0.810, e = 0.5) over 6 runs "
            "(range 0.800–0.850, thesis ≈ 0.83); Ψ < Φ in 5 of 6 runs (not at ν = 0.810, e = 0.5).",
            self.report,
        )

    def test_next_order(self):
        self.assertIn(
            "the largest 4θ component of C(θ) is a4_c = -0.0120 ± 0.0010 (ν = 0.810, e = 0); 1 of 6 runs have a "
            "4θ component of C(θ) with |value| ≥ 0.01",
            self.report,
        )
        self.assertIn(
            "the largest 4θ component of F_bc(θ) is a4_f = 0.0050 ± 0.0010 (ν = 0.700, e = 0); 0 of 6", self.report
        )

    def test_z_at_two_steps(self):
        self.assertIn("| 0.700 | 0 | 4.00 ± 0.10 | 4.30 ± 0.10 | +2.1σ |", self.report)
        self.assertIn("| 0.790 | 0 | 3.00 ± 0.10 | 3.00 ± 0.10 | +0.0σ |", self.report)
        self.assertIn(
            "2 pairs of runs at the default step and half of it; the largest difference of z "
            "(half − default) is +2.1σ (ν = 0.700, e = 0); z agrees within errors in 1 of 2 pairs.",
            self.report,
        )

    def test_collapse_table(self):
        rows = {
            (m.group(1), m.group(2)): [c.strip() for c in m.group(3).split("|")]
            for m in re.finditer(r"^\| (6\.2[789]) \| (\w+) \| (.*) \|$", self.report, re.M)
        }
        self.assertEqual(len(rows), 12, self.report)
        self.assertEqual(rows[("6.27", "main")], ["1.000", "0.000", "6", "0", "0", "5.00 (5.00)"])
        self.assertEqual(rows[("6.27", "floor")], ["1.000", "0.100", "6", "0", "0", "5.00 (5.00)"])
        self.assertEqual(rows[("6.27", "active")][0], "0.500")
        self.assertEqual(rows[("6.28", "main")][2:5], ["5", "1", "0"])
        self.assertEqual(rows[("6.29", "main")][2:5], ["5", "0", "1"])
        self.assertIn("1 of 6 runs with a ξ/ξ_el have a negative base with a non-integer", self.report)

    def test_bound(self):
        self.assertIn(
            "(p^s − p^bc)/p^bc exceeds ξ/ξ_el − 1 by more than 2 combined errors in 3 of 6 runs with a ξ/ξ_el "
            "(largest: ν = 0.810, e = 0.5, 1000.00 ± 0.10 against ξ/ξ_el − 1 = 2.50).",
            self.report,
        )

    def test_identity(self):
        self.assertIn("the 2θ amplitude of σ(θ)/⟨σ⟩ from 0.0010 to 0.0060", self.report)
        self.assertIn(
            "largest difference +3.0σ (ν = 0.790, e = 0.5: 0.26 against 0.200 ± 0.020), within errors "
            "in 5 of 6 runs",
            self.report,
        )


if __name__ == "__main__":
    unittest.main()


class Ch6NetworkMakeTest(unittest.TestCase):
    """The make rules of the force-network tables, runs and figures (pipelines/ch6.mk) at
    SIZE=test, read from `make -n` with every program's stamp present (nothing is run)."""

    ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
    STAMPS = (
        "gf-pack",
        "gf-shear",
        "gf-correlate",
        "gf-incline",
        "gf-kinetic",
        "gf-network",
        "libgranflow_statistics.so",
    )

    def plan(self, *variables):
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "build", "stamps"))
            for prog in self.STAMPS:
                with open(os.path.join(d, "build", "stamps", prog + ".stamp"), "w") as fh:
                    fh.write("0\n")
            res = subprocess.run(
                synthetic.scratch_make(d, "-n") + list(variables) + ["quick-files"],
                cwd=self.ROOT,
                capture_output=True,
                text=True,
            )
            self.assertEqual(res.returncode, 0, res.stderr)
            return re.sub(r"[ \t]+", " ", res.stdout.replace(d, "TMP").replace("\\\n", " "))

    def test_tables_runs_and_figures(self):
        # test.mk makes the table without a correlation table (64 grains: no finite ξ_el); the
        # other sizes read the chapter-5 table.
        out = self.plan(
            "CH6_NETWORK_CORRELATION=$(RUNS)/ch5_correlate.h5", "CH6_NETWORK_NU=$(CH5_NU)", "CH6_NETWORK_E=$(CH5_E)"
        )
        grid = " ".join(
            f"TMP/runs/shear_nu{nu}_e{e}_mu0.00_r1e-02_s1.h5" for e in ("0.00", "0.92") for nu in ("0.500", "0.700")
        )
        self.assertIn(
            "gf-network --quiet -o TMP/runs/ch6_network.h5 --correlation TMP/runs/ch5_correlate.h5 --from-strain 0.05 "
            f"--detect-transient {grid}\n",
            out,
        )
        pair, half = (f"TMP/runs/{k}_nu0.700_e0.00_mu0.00_r1e-02_s1.h5" for k in ("shear", "halfstep"))
        self.assertIn(
            "gf-network --quiet -o TMP/runs/ch6_network_halfstep.h5 --from-strain 0.05 --detect-transient "
            f"{pair} {half}\n",
            out,
        )
        # The half-step run is the default-step run of the same name at half the strain step with
        # twice the steps between frames (the same strain per frame).
        default = re.search(rf"^.*gf-shear .* -o {pair} .*$", out, re.M).group(0)
        halved = re.search(rf"^.*gf-shear .* -o {half} .*$", out, re.M).group(0)
        self.assertIn("--strain-step 1e-3 --frame-every 10", default)
        self.assertEqual(
            halved,
            default.replace(pair, half).replace(
                "--strain-step 1e-3 --frame-every 10", "--strain-step 0.0005 --frame-every $((2 * 10))"
            ),
        )
        self.assertEqual(out.count(f"-o {half} "), 1)
        self.assertIn(
            "ch6_network.py --figure 6.5 --restitution 0.00 --nu 0.790 TMP/runs/ch6_network.h5 "
            "TMP/figures/fig6_5.png",
            out,
        )
        for k in (6, 8):
            self.assertIn(f"ch6_network.py --figure 6.{k} TMP/runs/ch6_network.h5 TMP/figures/fig6_{k}.png", out)
        self.assertIn(
            "ch6_network.py --figure 6.7 --halfstep TMP/runs/ch6_network_halfstep.h5 "
            "TMP/runs/ch6_network.h5 TMP/figures/fig6_7.png",
            out,
        )
        self.assertRegex(
            out,
            r"pipelines/report .*--ch6-network TMP/runs/ch6_network\.h5 "
            r"--ch6-network-halfstep TMP/runs/ch6_network_halfstep\.h5",
        )
        # The kinetic figures keep their own rule.
        self.assertIn("ch6_kinetic.py --restitutions 0.92 0.75", out)
        self.assertNotIn("ch6_kinetic.py --restitutions  ", out)

    def test_without_half_step_runs(self):
        out = self.plan("CH6_HALFSTEP_NU=")
        self.assertNotIn("halfstep", out)
        self.assertIn("ch6_network.py --figure 6.7 TMP/runs/ch6_network.h5 TMP/figures/fig6_7.png", out)
        self.assertRegex(out, r"pipelines/report .*--ch6-network TMP/runs/ch6_network\.h5 ")

    def test_test_size_grid(self):
        # test.mk: no correlation table, only the run with long-lived contacts.
        out = self.plan()
        self.assertIn(
            "gf-network --quiet -o TMP/runs/ch6_network.h5 --from-strain 0.05 --detect-transient "
            "TMP/runs/shear_nu0.700_e0.00_mu0.00_r1e-02_s1.h5\n",
            out,
        )
        self.assertNotIn("--correlation", out)
