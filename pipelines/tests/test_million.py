"""bench/million.sh (docs/performance.md, "A million grains") at a smoke size: every program
runs on the real files, and every figure of its table is read from them. The table's numbers
are checked against what the run must give: a row per program, times and memory > 0, the
engine's heap per grain read from gf-shear's summary line (the format the script parses) and
under the 1 KB the physics test asserts, the trajectory's bytes per frame from the file, and
the commands beside the rows."""
import csv
import os
import shutil
import subprocess
import tempfile
import unittest

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
SCRIPT = os.path.join(ROOT, "bench", "million.sh")
BIN = os.environ.get("GRANFLOW_BIN", os.path.join(ROOT, "build", "bin"))
PROGRAMS = ["gf-pack", "gf-shear warm-up", "gf-shear 1T", "gf-shear 2T", "gf-correlate", "gf-network",
            "gf-kinetic", "gf-stz d2min"]


@unittest.skipUnless(shutil.which("bash") and os.access("/usr/bin/time", os.X_OK)
                     and os.path.exists(os.path.join(BIN, "gf-shear")), "needs bash, GNU time and the programs")
class MillionSmoke(unittest.TestCase):
    def test_smoke_table(self):
        with tempfile.TemporaryDirectory() as out:
            env = dict(os.environ, BIN=BIN, OUT=out, WARM="20", STEPS="20", FRAMES="4")
            done = subprocess.run(["bash", SCRIPT, "500"], env=env, capture_output=True, text=True, timeout=300)
            self.assertEqual(done.returncode, 0, done.stderr)
            with open(os.path.join(out, "million.tsv")) as f:
                rows = list(csv.DictReader(f, delimiter="\t"))
            self.assertEqual([r["program"] for r in rows], PROGRAMS)
            for r in rows:
                self.assertEqual(r["N"], "500")
                self.assertGreater(float(r["wall_s"]), 0.0, r)
                self.assertGreater(float(r["peak_rss_MiB"]), 0.0, r)
                self.assertTrue(r["command"].startswith(BIN), r)
            shear = {r["program"]: r for r in rows if r["program"].startswith("gf-shear")}
            for r in shear.values():
                self.assertLess(0.0, float(r["engine_B_per_grain"]))
                self.assertLess(float(r["engine_B_per_grain"]), 1024.0)
                self.assertGreater(float(r["ns_per_grain_step"]), 0.0)
                self.assertGreater(float(r["cpu_ns_per_grain_step"]), 0.0)
                self.assertGreater(float(r["sweeps_per_step"]), 0.0)
            # A timed run stores step 0 and FRAMES frames; its size per frame is the file's.
            one = shear["gf-shear 1T"]
            self.assertEqual(one["frames"], "5")
            size = os.path.getsize(os.path.join(out, "n500", "run_t1.h5"))
            self.assertAlmostEqual(float(one["kB_per_frame"]), size / 5 / 1e3, delta=0.5)
            # The thread count does not change the trajectory: the same sweeps per step.
            self.assertEqual(shear["gf-shear 1T"]["sweeps_per_step"], shear["gf-shear 2T"]["sweeps_per_step"])
            with open(os.path.join(out, "million.md")) as f:
                table = f.read()
            self.assertEqual(table.count("\n| gf-"), len(PROGRAMS))
            self.assertIn("`" + BIN + "/gf-pack -n 500", table)

    def test_tiled_start(self):
        # TILE=2 at 2000 grains: 500 grains sheared to strain 2, tiled 2 x 2 into the packing
        # of the timed runs: four times the grains in a box twice as wide and tall, the
        # radii and positions those of the run's last frame.
        import h5py
        import numpy as np
        with tempfile.TemporaryDirectory() as out:
            env = dict(os.environ, BIN=BIN, OUT=out, TILE="2", WARM="5", STEPS="5", FRAMES="1",
                       ONLY="pack warm shear1")
            done = subprocess.run(["bash", SCRIPT, "2000"], env=env, capture_output=True, text=True, timeout=300)
            self.assertEqual(done.returncode, 0, done.stderr)
            with open(os.path.join(out, "million.tsv")) as f:
                rows = list(csv.DictReader(f, delimiter="\t"))
            self.assertEqual([(r["program"], r["N"]) for r in rows],
                             [("gf-pack", "500"), ("gf-shear to strain 2", "500"), ("gf-pack --tile 2", "2000"),
                              ("gf-shear warm-up", "2000"), ("gf-shear 1T", "2000")])
            d = os.path.join(out, "n2000")
            with h5py.File(os.path.join(d, "tile_run.h5")) as run, h5py.File(os.path.join(d, "pack.h5")) as pack:
                small, big = run["particles/grains"], pack["particles/grains"]
                self.assertEqual(len(big["radius"]), 4 * len(small["radius"]))
                # At strain 2 the run's offset is a whole number of box widths, and so is the
                # packing's (twice it).
                np.testing.assert_allclose(np.diag(big["box/edges/value"][-1]), 2 * np.diag(small["box/edges/value"][-1]))
                big_lx = big["box/edges/value"][-1][0][0]
                offset = big["box/edges/value"][-1][1][0]
                self.assertLess(min(offset, big_lx - offset), 1e-9 * big_lx)
                self.assertEqual(sorted(big["radius"][()]), sorted(np.tile(small["radius"][()], 4)))
                lx = small["box/edges/value"][-1][0][0]
                folded = np.sort(np.mod(big["position/value"][0][:, 0], lx))
                np.testing.assert_allclose(folded, np.sort(np.tile(np.mod(small["position/value"][-1][:, 0], lx), 4)),
                                           atol=1e-9)
                self.assertEqual(pack["parameters"].attrs["grains"], 2000)


if __name__ == "__main__":
    unittest.main()
