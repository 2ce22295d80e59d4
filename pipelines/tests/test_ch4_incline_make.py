"""The chapter-4 incline fragment of Makefile.sweeps (pipelines/ch4_incline.mk), dry run at
SIZE=test with stamps present: run names carry their parameters into the commands, the start
is made once, the μ = 0.4 runs branch from the end of a μ = 0 run (after it, and again when it
changes), the θ_c sweep and the bulk table get the right runs, and `ch4-files` includes the
incline figures. Nothing is built or run."""
import os
import re
import subprocess
import tempfile
import unittest

from granflow.hdf5 import text
from synthetic import scratch_make

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


class Ch4InclineMakeTest(unittest.TestCase):
    def dry_run(self, *targets, **variables):
        with tempfile.TemporaryDirectory() as d:
            stamps = os.path.join(d, "build", "stamps")
            os.makedirs(stamps)
            for prog in ("gf-pack", "gf-shear", "gf-incline", "libgranflow_statistics.so"):
                with open(os.path.join(stamps, prog + ".stamp"), "w") as fh:
                    fh.write("0\n")
            args = scratch_make(d, "-n")
            args += [f"{k}={v}" for k, v in variables.items()] + [t.replace("TMP", d) for t in targets]
            res = subprocess.run(args, cwd=ROOT, capture_output=True, text=True)
            self.assertEqual(res.returncode, 0, res.stderr)
            return re.sub(r"[ \t]+", " ", res.stdout.replace(d, "TMP").replace("\\\n", " "))

    def test_incline_commands(self):
        out = self.dry_run("ch4-incline-files", INCLINE_ANGLES_MU0="20 22", INCLINE_CRITICAL_ANGLES="5")
        self.assertEqual(out.count("gf-pack --quiet --incline --width 10 --height 12 --seed 1"), 1, out)
        runs = re.findall(
            r"gf-incline --quiet -i TMP/runs/incline_pack_w10_h12_s1\.h5 -o "
            r"TMP/runs/incline_th(\S+)_e(\S+)_mu(\S+)_s1\.h5 --angle (\S+) --restitution (\S+) "
            r"--friction (\S+) --time 20 --time-step 5e-3 --from-time 5 ",
            out,
        )
        got = sorted((float(a), float(mu)) for _, _, _, a, _, mu in runs)
        self.assertEqual(got, [(5, 0), (20, 0), (22, 0)])
        for th, e, mu, angle, e2, mu2 in runs:
            self.assertEqual((th, e, mu), (angle, e2, mu2))
        # μ = 0.4 branches from the last frame of the μ = 0 run at INCLINE_MU04_PARENT (20°), with
        # the branch settings; made after its parent, once.
        branch = (
            "gf-incline --quiet -i TMP/runs/incline_th20_e0.50_mu0.00_s1.h5 -o "
            "TMP/runs/incline_branch_th30_e0.50_mu0.40_s1_from20.h5 --angle 30 --restitution 0.50 --friction 0.40 "
            "--frame -1 --time 10 --time-step 5e-3 --from-time 2 --frame-every 1000"
        )
        self.assertEqual(out.count(branch), 1, out)
        self.assertLess(out.index("-o TMP/runs/incline_th20_e0.50_mu0.00_s1.h5"), out.index(branch))
        self.assertRegex(
            out,
            r"incline_bulk\.py .* -o TMP/runs/ch4_incline\.h5 TMP/runs/incline_th20_\S+ "
            r"TMP/runs/incline_th22_\S+ TMP/runs/incline_branch_th30_e0\.50_mu0\.40_s1_from20\.h5",
        )
        self.assertRegex(
            out,
            r"critical_angle\.py --window 10 -o TMP/runs/ch4_critical_angle\.h5 "
            r"TMP/runs/incline_th20_\S+ TMP/runs/incline_th22_\S+ TMP/runs/incline_th5_\S+\n",
        )
        for k in (7, 8, 9, 10):
            self.assertIn(f"TMP/figures/fig4_{k}.png", out)
        # Fig 4.10 reads the shear sweep, which has the μ = 0.4 rows too.
        self.assertIn("shear_nu0.700_e0.50_mu0.40_r1e-02_s1.h5", out)

    def test_branch_settings_and_any_name(self):
        # A coarser tolerance reaches the command; any branched name can be asked for, and its
        # parent (any angle, μ = 0, same e and seed) is made first from the pack.
        out = self.dry_run("TMP/runs/incline_branch_th25_e0.50_mu0.40_s1_from22.h5", INCLINE_BRANCH_TOLERANCE="1e-8")
        self.assertIn("gf-pack --quiet --incline --width 10 --height 12 --seed 1", out)
        self.assertRegex(
            out,
            r"gf-incline --quiet -i TMP/runs/incline_pack_w10_h12_s1\.h5 -o "
            r"TMP/runs/incline_th22_e0\.50_mu0\.00_s1\.h5 --angle 22 .* --time 20 ",
        )
        self.assertRegex(
            out,
            r"-i TMP/runs/incline_th22_e0\.50_mu0\.00_s1\.h5 -o "
            r"TMP/runs/incline_branch_th25_e0\.50_mu0\.40_s1_from22\.h5 --angle 25 .* --frame -1 "
            r"--time 10 --time-step 5e-3 --from-time 2 --tolerance 1e-8 ",
        )
        # Without a parent angle the μ = 0.4 runs start from the pack with the μ = 0 settings.
        out = self.dry_run("ch4-incline-files", INCLINE_MU04_PARENT="")
        self.assertRegex(
            out,
            r"-i TMP/runs/incline_pack_w10_h12_s1\.h5 -o TMP/runs/incline_th30_e0\.50_mu0\.40_s1\.h5 "
            r"--angle 30 .* --time 20 ",
        )
        self.assertNotIn("_from", out)

    def test_branch_remade_after_its_parent(self):
        # With every file present and up to date, a newer parent makes the branch (and only the
        # runs depending on it) out of date.
        with tempfile.TemporaryDirectory() as d:
            args = scratch_make(d, "-q")
            os.makedirs(f"{d}/build/stamps")
            os.makedirs(f"{d}/runs")
            files = [
                f"{d}/build/stamps/gf-incline.stamp",
                f"{d}/build/stamps/gf-pack.stamp",
                f"{d}/runs/incline_pack_w10_h12_s1.h5",
                f"{d}/runs/incline_th20_e0.50_mu0.00_s1.h5",
                f"{d}/runs/incline_branch_th30_e0.50_mu0.40_s1_from20.h5",
            ]
            for k, path in enumerate(files):
                with open(path, "w") as fh:
                    fh.write("x\n")
                os.utime(path, (1000 + k, 1000 + k))
            branch = files[-1]
            self.assertEqual(subprocess.run(args + [branch], cwd=ROOT).returncode, 0)
            os.utime(files[3], (2000, 2000))  # the parent was remade
            self.assertEqual(subprocess.run(args + [branch], cwd=ROOT).returncode, 1)
            self.assertEqual(subprocess.run(args + [files[3]], cwd=ROOT).returncode, 0)

    def test_ch4_includes_incline(self):
        out = self.dry_run("ch4-files")
        self.assertIn("ch4_incline_snapshot.py", out)
        self.assertIn("ch4_consistent_rheology.py", out)


@unittest.skipUnless(
    os.path.isfile(os.path.join(os.environ.get("GRANFLOW_BIN", "-"), "gf-incline")),
    "GRANFLOW_BIN (the built gf-* programs) not given; ctest sets it",
)
class Ch4InclineBranchRunTest(unittest.TestCase):
    """The branch rule for real at SIZE=test (a 10 x 12 layer; seconds): the pack, the 20° μ = 0
    parent, the 30° μ = 0.4 branch from its last frame, the bulk table with the branch's row and
    its parent, and Fig 4.10."""

    def test_branch_run_table_and_figure(self):
        with tempfile.TemporaryDirectory() as d:
            stamps = os.path.join(d, "stamps")
            os.makedirs(stamps)
            for prog in ("gf-pack", "gf-shear", "gf-incline", "libgranflow_statistics.so"):
                with open(os.path.join(stamps, prog + ".stamp"), "w") as fh:
                    fh.write("0\n")
            make = [
                "make",
                "--no-print-directory",
                "-f",
                "Makefile.sweeps",
                "SIZE=test",
                f"BIN={os.environ['GRANFLOW_BIN']}",
                f"STAMPS={stamps}",
                f"RUNS={d}/runs",
                f"FIGURES={d}/figures",
                "PYTHON=/usr/bin/python3",
            ]
            targets = [f"{d}/runs/ch4_incline.h5", f"{d}/figures/fig4_10.png"]
            res = subprocess.run(make + targets, cwd=ROOT, capture_output=True, text=True)
            self.assertEqual(res.returncode, 0, res.stdout + res.stderr)
            import h5py

            branch = f"{d}/runs/incline_branch_th30_e0.50_mu0.40_s1_from20.h5"
            with h5py.File(branch, "r") as f:
                p = f["parameters"].attrs
                self.assertEqual((p["angle"], p["friction"], p["parent_angle"], p["parent_friction"]), (30, 0.4, 20, 0))
                parent = p["input"]
                self.assertEqual(text(parent), f"{d}/runs/incline_th20_e0.50_mu0.00_s1.h5")
            with h5py.File(targets[0], "r") as f:
                rows = [os.path.basename(text(x)) for x in f["runs/input"][...]]
                k = rows.index(os.path.basename(branch))
                self.assertAlmostEqual(f["runs/friction"][k], 0.4)
                start = f["runs/start"][k]
                self.assertEqual(text(start), "incline_th20_e0.50_mu0.00_s1.h5")
                self.assertAlmostEqual(f["runs/start_time"][k], 20, places=6)  # the parent's 20 τ
                self.assertEqual(f["runs/start_friction"][k], 0)
            with open(targets[1], "rb") as fh:
                self.assertEqual(fh.read(8), b"\x89PNG\r\n\x1a\n")
            # Up to date now; a remade parent makes the branch and the table out of date.
            self.assertEqual(subprocess.run(make + ["-q"] + targets, cwd=ROOT).returncode, 0)
            os.utime(f"{d}/runs/incline_th20_e0.50_mu0.00_s1.h5")
            self.assertEqual(subprocess.run(make + ["-q", branch], cwd=ROOT).returncode, 1)


if __name__ == "__main__":
    unittest.main()
