"""Smoke tests of the chapter-4 figure scripts and report section on a small synthetic sweep:
each script runs, writes its PNG (atomically) and the report quotes the thesis beside our values."""
import glob
import os
import tempfile
import unittest

import numpy as np

from analysis import steady_state as ss

import synthetic  # a sibling module: the tests' own fixtures


class Ch4OutputsTest(unittest.TestCase, synthetic.ScriptRunner):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = cls.tmp.name
        rng = np.random.default_rng(5)
        n = 1200
        sweep, cls.bagnold = [], []
        for e in (0.0, 0.5):
            for nu in (0.6, 0.8):
                scale = 1 / (0.85 - nu) ** 2
                p = scale * (2 + 0.2 * synthetic.ar1(0.8, n, rng))
                path = os.path.join(d, f"shear_nu{nu:.3f}_e{e:.2f}.h5")
                synthetic.write_run(
                    path,
                    0.9 * p,
                    0.1 * p,
                    0.35 * p,
                    np.full(n, 0.3 * scale),
                    packing_fraction=nu,
                    restitution=e,
                    rng=rng,
                )
                sweep.append(path)
        for rate in (1e-2, 1e2):
            p = 2 + 0.2 * synthetic.ar1(0.8, n, np.random.default_rng(9))
            path = os.path.join(d, f"shear_r{rate:.0e}.h5")
            synthetic.write_run(
                path,
                0.9 * p * rate**2,
                0.1 * p * rate**2,
                0.35 * p * rate**2,
                np.full(n, 0.3 * rate**2),
                rate=rate,
                rng=np.random.default_rng(9),
            )
            cls.bagnold.append(path)
        cls.sweep_table, cls.bagnold_table = os.path.join(d, "ch4_sweep.h5"), os.path.join(d, "ch4_bagnold.h5")
        ss.write_table(cls.sweep_table, ss.analyse(sweep, 0.5), 0.5, "test")
        ss.write_table(cls.bagnold_table, ss.analyse(cls.bagnold, 0.5), 0.5, "test")
        cls.packing = synthetic.write_packing(os.path.join(d, "pack.h5"))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_figures(self):
        d = self.tmp.name
        calls = {
            "fig4_1.png": lambda out: ("plot/ch4_snapshot.py", self.bagnold[0], out),
            "fig4_2.png": lambda out: ("plot/ch4_bagnold.py", "--detect-transient", out, *self.bagnold),
            "fig4_3.png": lambda out: ("plot/ch4_invariants.py", "--detect-transient", self.bagnold[0], out),
            "fig4_4.png": lambda out: ("plot/ch4_rheology.py", self.sweep_table, out),
            "fig4_5.png": lambda out: ("plot/ch4_pressure_parts.py", self.sweep_table, out),
            "fig4_6.png": lambda out: ("plot/ch4_static_pressure.py", self.sweep_table, out),
        }
        for name, command in calls.items():
            out = os.path.join(d, name)
            with self.subTest(figure=name):
                self.run_script(*command(out))
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
            "--ch4-sweep",
            self.sweep_table,
            "--ch4-bagnold",
            self.bagnold_table,
            "--ch4-reference",
            self.bagnold[0],
            self.packing,
        )
        with open(out) as fh:
            text = fh.read()
        self.assertNotIn("Step dependence", text)
        self.assertIn("## Packings", text)
        for needle in (
            "## Chapter 4",
            "(thesis l. 404)",
            "(thesis l. 377)",
            "| 0.800 |",
            "γ̇ = 100",
            "Flyvbjerg-Petersen",
        ):
            self.assertIn(needle, text)
        # Identical normalised traces at the two rates: Bagnold difference of zero.
        self.assertRegex(text, r"\| p/\(γ̇²m\) \| [^|]+ \| [^|]+ \| \+0\.0 \|")


if __name__ == "__main__":
    unittest.main()


class StepNoteTest(unittest.TestCase):
    """The report's step-dependence paragraph (report/steps.py) on a constructed classes file with known counts."""

    CSV = """# convergence.py classes at the default step 0.001, activation predicted-gap
packing_fraction,restitution,friction,grains,observable,label,class,default_value,default_error,limit,limit_error,exponent,exponent_error
0.800,0.50,0.00,1000,p,p/(mγ̇²),converged,90,1,nan,nan,nan,nan
0.800,0.00,0.00,1000,p,p/(mγ̇²),converging,100,1,99,0.5,nan,nan
0.820,0.92,0.00,1000,p,p/(mγ̇²),converging,110,1,100,1,nan,nan
0.760,0.50,0.00,1000,p,p/(mγ̇²),unsettled,50,5,nan,nan,nan,nan
0.800,0.50,0.00,1000,s_over_p,s/p,converged,0.3,0.001,nan,nan,nan,nan
0.800,0.50,0.00,1000,z,z (age ≥ 2),regularisation-dependent,0.6,0.01,nan,nan,0.8,0.1
0.800,0.00,0.00,1000,d2min_black,D²min: black fraction,converged,0.03,0.003,nan,nan,nan,nan
"""

    def setUp(self):
        from report import steps

        self.report = steps
        self.tmp = tempfile.TemporaryDirectory()
        self.path = os.path.join(self.tmp.name, "classes.csv")
        with open(self.path, "w") as fh:
            fh.write(self.CSV)

    def tearDown(self):
        self.tmp.cleanup()

    def test_counts_and_near_limit(self):
        classes = self.report.read_step_classes(self.path)
        text = "\n".join(self.report.step_note(classes, "ch4", self.path))
        self.assertIn("over the convergence study's 4 state points", text)
        self.assertIn("activation predicted-gap", text)
        # 100 against 99 ± 0.5 is within 2 %; 110 against 100 is not.
        self.assertIn("p/(mγ̇²): converged 1, converging 2 (at 1 of them the default step within 2 % of the limit or "
                      "its errors), unsettled 1", text)
        self.assertIn("s/p: converged 1", text)
        self.assertNotIn("z (age", text)
        net = "\n".join(self.report.step_note(classes, "ch6_network", self.path))
        self.assertIn("z (age ≥ 2): regularisation-dependent 1", net)
        self.assertIn("make incline-step", "\n".join(self.report.step_note(classes, "incline", self.path)))
        self.assertIn("D²min: black fraction: converged 1", "\n".join(self.report.step_note(classes, "ch6_d2min", self.path)))
        self.assertEqual(self.report.step_note(None, "ch4", self.path), [])
