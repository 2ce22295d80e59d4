"""The chapter-4 incline fragment of Makefile.sweeps (pipelines/ch4_incline.mk), dry run at
SIZE=test with stamps present: run names carry their parameters into the commands, the start
is made once, the θ_c sweep and the bulk table get the right runs, and `ch4-files` includes
the incline figures. Nothing is built or run."""
import os
import re
import subprocess
import tempfile
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


class Ch4InclineMakeTest(unittest.TestCase):
    def dry_run(self, *targets, **variables):
        with tempfile.TemporaryDirectory() as d:
            stamps = os.path.join(d, "build", "stamps")
            os.makedirs(stamps)
            for prog in ("gf-pack", "gf-shear", "gf-incline"):
                with open(os.path.join(stamps, prog + ".stamp"), "w") as fh:
                    fh.write("0\n")
            args = ["make", "-n", "--no-print-directory", "-f", "Makefile.sweeps", "SIZE=test",
                    f"BUILD={d}/build", f"RUNS={d}/runs", f"FIGURES={d}/figures"]
            args += [f"{k}={v}" for k, v in variables.items()] + list(targets)
            res = subprocess.run(args, cwd=ROOT, capture_output=True, text=True)
            self.assertEqual(res.returncode, 0, res.stderr)
            return re.sub(r"[ \t]+", " ", res.stdout.replace(d, "TMP").replace("\\\n", " "))

    def test_incline_commands(self):
        out = self.dry_run("ch4-incline-files", INCLINE_ANGLES_MU0="20 22", INCLINE_CRITICAL_ANGLES="5")
        self.assertEqual(out.count("gf-pack --quiet --incline --width 10 --height 5 --seed 1"), 1, out)
        runs = re.findall(r"gf-incline --quiet -i TMP/runs/incline_pack_w10_h5_s1\.h5 -o "
                          r"TMP/runs/incline_th(\S+)_e(\S+)_mu(\S+)_s1\.h5 --angle (\S+) --restitution (\S+) "
                          r"--friction (\S+)", out)
        got = sorted((float(a), float(mu)) for _, _, _, a, _, mu in runs)
        self.assertEqual(got, [(5, 0), (20, 0), (22, 0), (30, 0.4)])
        for th, e, mu, angle, e2, mu2 in runs:
            self.assertEqual((th, e, mu), (angle, e2, mu2))
        self.assertRegex(out, r"incline_bulk\.py .* -o TMP/runs/ch4_incline\.h5 TMP/runs/incline_th20_\S+ "
                              r"TMP/runs/incline_th22_\S+ TMP/runs/incline_th30_e0\.50_mu0\.40_s1\.h5")
        self.assertRegex(out, r"critical_angle\.py --window 10 -o TMP/runs/ch4_critical_angle\.h5 "
                              r"TMP/runs/incline_th20_\S+ TMP/runs/incline_th22_\S+ TMP/runs/incline_th5_\S+\n")
        for k in (7, 8, 9, 10):
            self.assertIn(f"TMP/figures/fig4_{k}.png", out)
        # Fig 4.10 reads the shear sweep, which now has the μ = 0.4 rows.
        self.assertIn("shear_nu0.700_e0.50_mu0.40_r1e-02_s1.h5", out)

    def test_ch4_includes_incline(self):
        out = self.dry_run("ch4-files")
        self.assertIn("ch4_incline_snapshot.py", out)
        self.assertIn("ch4_consistent_rheology.py", out)


if __name__ == "__main__":
    unittest.main()
