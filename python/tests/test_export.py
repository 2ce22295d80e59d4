"""`python3 -m granflow export` (granflow/export.py) against plain h5py reads of the same runs, made
by the built programs (GRANFLOW_BIN): a 64-grain gf-shear run at ν = 0.8 (contacts in every
frame, a Lees–Edwards offset δ ≠ 0 at the exported frames), a gf-incline run (fixed base grains,
open top) and a gf-pack packing, exported to GSD and read back with gsd.hoomd and with
MDAnalysis, frame by frame: the box (lengths, tilt xy = δ/Ly), positions (the documented
translation by −(Lx/2, Ly/2), modulo the tilted lattice, inside HOOMD's box), and every contact's
branch vector as the minimum image in the GSD box (which fails for a wrong tilt), diameters,
masses, types, velocities, spins (from angmom and moment_inertia), bonds and their three force
arrays, the per-grain force; then bad inputs: exit 2, one line, no output and no temporary left.

Run as a script (ctest's python.test_export): exit 77 (skipped, said on stderr) only when gsd or
MDAnalysis cannot be imported (Debian: python3-gsd, python3-mdanalysis; Makefile.sweeps'
deps-test installs them)."""
import math
import os
import subprocess
import sys
import tempfile
import time
import unittest
import warnings

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import programs  # noqa: E402  (a sibling module: the tests' inputs)

try:
    import gsd.hoomd

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # MDAnalysis 2.4's imports warn (xdrlib) on Python 3.11
        import MDAnalysis
    MISSING = None
except ImportError as e:
    MISSING = str(e)

SKIP = 77
# gsd.hoomd.open's read mode: "rb" in gsd 2 (Debian bookworm's 2.7), "r" from gsd 3.
READ = "r" if not MISSING and int(gsd.__version__.split(".")[0]) >= 3 else "rb"
PYTHONPATH = os.pathsep.join(
    [os.path.join(programs.REPO, "python")] + ([os.environ["PYTHONPATH"]] if os.environ.get("PYTHONPATH") else [])
)
FRAMES = "2:21:4"  # 2, 6, 10, 14, 18 of the 21 frames of programs.shear_run
SELECTED = list(range(2, 21, 4))


def export(*args):
    """`python3 -m granflow export ARGS` -> CompletedProcess (text)."""
    env = dict(os.environ, PYTHONPATH=PYTHONPATH)
    return subprocess.run(
        [sys.executable, "-m", "granflow", "export", *args], capture_output=True, text=True, env=env
    )


def min_image(d, box):
    """The minimum images of separations d [C][2] in a HOOMD box [Lx, Ly, Lz, xy, ...]: lattice
    vectors a1 = (Lx, 0), a2 = (xy·Ly, Ly) (HOOMD's convention, as a reader of the file applies it)."""
    lx, ly, xy = (float(box[i]) for i in (0, 1, 3))
    d = np.array(d, dtype=np.float64)
    n = np.round(d[:, 1] / ly)
    d[:, 0] -= n * xy * ly
    d[:, 1] -= n * ly
    d[:, 0] -= np.round(d[:, 0] / lx) * lx
    return d


def fractional(position, box):
    """HOOMD's fractional coordinates (x − xy·y)/Lx, y/Ly of positions [N][≥2]."""
    lx, ly, xy = (float(box[i]) for i in (0, 1, 3))
    p = np.asarray(position, dtype=np.float64)
    return (p[:, 0] - xy * p[:, 1]) / lx, p[:, 1] / ly


def spin(frame):
    """ω from HOOMD's angmom P and orientation q: S = ½ im(q* ⊗ P), ω = S_z / I_z."""
    q = frame.particles.orientation.astype(np.float64)
    p = frame.particles.angmom.astype(np.float64)
    s_z = 0.5 * (q[:, 0] * p[:, 3] - q[:, 3] * p[:, 0] + q[:, 1] * p[:, 2] - q[:, 2] * p[:, 1])
    return s_z / frame.particles.moment_inertia[:, 2].astype(np.float64)


def mda_tilt(dimensions, ly):
    """xy as MDAnalysis' dimensions [A, B, C, α, β, γ] give it: MDAnalysis 2.4's GSD reader puts
    arccos of the tilt factors into the angles (α = arccos xy, β = γ = 90); a reader converting
    HOOMD's box properly gives γ with cot γ = xy and B = Ly·√(1 + xy²)."""
    alpha, gamma = math.radians(dimensions[3]), math.radians(dimensions[5])
    if abs(dimensions[5] - 90) > 1e-4:
        return 1 / math.tan(gamma)
    return math.cos(alpha)


def forces_by_grain(g, first, last, grains):
    """|Σ contact forces| per grain from the H5MD columns (h5py), independently of granflow."""
    c = g.file["contacts"]
    pair = c["pair"][first:last]
    b = c["branch"][first:last]
    n = b / np.linalg.norm(b, axis=1)[:, None]
    t = np.column_stack((-n[:, 1], n[:, 0]))
    f = c["normal_force"][first:last][:, None] * n + c["tangential_force"][first:last][:, None] * t
    total = np.zeros((grains, 2))
    for (i, j), fij in zip(pair, f):
        total[i] += fij
        total[j] -= fij
    return np.hypot(total[:, 0], total[:, 1])


@unittest.skipIf(MISSING, f"gsd or MDAnalysis missing: {MISSING}")
class ExportTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = cls.tmp.name
        cls.shear = programs.shear_run(cls.dir, packing_fraction=0.8)
        cls.pack = os.path.join(cls.dir, "pack_nu0.800.h5")
        cls.incline_pack, cls.incline = programs.incline_run(cls.dir)
        cls.out = os.path.join(cls.dir, "out")
        os.mkdir(cls.out)
        cls.gsd = os.path.join(cls.out, "shear.gsd")
        result = export(cls.shear, "-o", cls.gsd, "--frames", FRAMES, "--quiet")
        if result.returncode != 0:
            raise AssertionError(f"export failed ({result.returncode}): {result.stderr}")
        cls.quiet_stderr = result.stderr

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def check_frame(self, g, frame, k, contacts=True):
        """GSD frame `frame` against frame k of the H5MD file open as g (/particles/grains)."""
        grains = g["particles/grains"]
        edges = grains["box/edges/value"][k]
        lx, ly, offset = float(edges[0, 0]), float(edges[1, 1]), float(edges[1, 0])
        periodic_y = "lees_edwards" in g.file
        if periodic_y:
            self.assertEqual(offset, g.file["lees_edwards/offset/value"][k])
        box = frame.configuration.box
        self.assertEqual(frame.configuration.dimensions, 2)
        self.assertEqual(int(frame.configuration.step), int(grains["position/step"][k]))
        self.assertAlmostEqual(float(box[0]), lx, delta=1e-6 * lx)
        if periodic_y:
            self.assertAlmostEqual(float(box[1]), ly, delta=1e-6 * ly)
            self.assertAlmostEqual(float(box[3]), offset / ly, delta=1e-6)
        else:
            self.assertGreaterEqual(float(box[1]), ly * (1 - 1e-6))
            self.assertEqual(float(box[3]), 0.0)
        np.testing.assert_array_equal(box[4:], [0, 0])
        self.assertEqual(frame.log["frame"][0], k)
        self.assertEqual(frame.log["lees_edwards_offset"][0], offset)
        self.assertEqual(frame.log["time"][0], grains["position/time"][k])

        # Grains.
        r = grains["radius"][...]
        n = len(r)
        self.assertEqual(frame.particles.N, n)
        self.assertEqual(list(frame.particles.types), ["free", "fixed"])
        np.testing.assert_array_equal(frame.particles.typeid, grains["fixed"][...])
        np.testing.assert_allclose(frame.particles.diameter, 2 * r, rtol=1e-6)
        np.testing.assert_allclose(frame.particles.mass, grains["mass"][...], rtol=1e-6)
        position = grains["position/value"][k]
        p = frame.particles.position.astype(np.float64)
        np.testing.assert_array_equal(p[:, 2], 0)
        fx, fy = fractional(p, box)  # inside HOOMD's box
        self.assertTrue(np.all((fx >= -0.5) & (fx < 0.5) & (fy >= -0.5) & (fy < 0.5)), "a grain outside the box")
        # The documented translation by −(Lx/2, Ly/2), modulo the lattice (a1 = (Lx, 0), a2 = (δ, Ly)).
        if periodic_y:
            d = p[:, :2] + [lx / 2, ly / 2] - position
            m2 = d[:, 1] / ly
            m1 = (d[:, 0] - np.round(m2) * offset) / lx
            np.testing.assert_allclose(m2, np.round(m2), atol=1e-5)
            np.testing.assert_allclose(m1, np.round(m1), atol=1e-5)
        else:  # an incline: untilted, y only shifted (the box widened about its centre)
            shift = p[:, 1] - position[:, 1]
            np.testing.assert_allclose(shift, shift[0], atol=1e-5 * ly)
            m1 = (p[:, 0] + lx / 2 - position[:, 0]) / lx
            np.testing.assert_allclose(m1, np.round(m1), atol=1e-5)
        velocity = grains["velocity/value"][k]
        scale = np.abs(velocity).max()
        np.testing.assert_allclose(frame.particles.velocity[:, :2], velocity, rtol=1e-6, atol=1e-6 * scale)
        np.testing.assert_array_equal(frame.particles.velocity[:, 2], 0)
        omega = grains["angular_velocity/value"][k]
        np.testing.assert_array_equal(frame.log["particles/angular_velocity"], omega)
        np.testing.assert_allclose(spin(frame), omega, rtol=1e-5, atol=1e-5 * max(1.0, np.abs(omega).max()))

        # Contacts as bonds.
        if not contacts:
            self.assertEqual(frame.bonds.N, 0)
            return 0
        if "contacts" in g.file:
            first, last = (int(v) for v in g.file["contacts/frame_offset"][k : k + 2])
        else:
            first = last = 0
        self.assertEqual(frame.bonds.N, last - first)
        self.assertEqual(list(frame.bonds.types), ["contact"])
        if last == first:
            for key in ("bonds/normal_force", "bonds/tangential_force", "bonds/binary_force"):
                self.assertEqual(len(frame.log[key]), 0)
            return 0
        c = g.file["contacts"]
        pair = c["pair"][first:last]
        np.testing.assert_array_equal(frame.bonds.group, pair)
        np.testing.assert_array_equal(frame.bonds.typeid, 0)
        np.testing.assert_array_equal(frame.log["bonds/normal_force"], c["normal_force"][first:last])
        np.testing.assert_array_equal(frame.log["bonds/tangential_force"], c["tangential_force"][first:last])
        np.testing.assert_array_equal(frame.log["bonds/binary_force"], c["binary_force"][first:last])
        np.testing.assert_allclose(
            frame.log["particles/force_magnitude"], forces_by_grain(g, first, last, n), rtol=1e-9, atol=1e-9
        )
        # Each contact's branch r_i − r_j, as a reader of the GSD file finds it (minimum image in
        # HOOMD's box), is the one the H5MD file stores: this checks the tilt's sign and size (a
        # wrong tilt moves the contacts across the top and bottom by a box-sized amount). The stored
        # branch is the step's, from the positions before it, so it differs from that of the stored
        # positions by about |v_i − v_j|·dt (≲ 0.01 here): hence a tolerance of 5 % of a diameter.
        branch = min_image(p[pair[:, 0], :2] - p[pair[:, 1], :2], box)
        np.testing.assert_allclose(branch, c["branch"][first:last], atol=0.05 * 2 * float(np.mean(r)))
        # Contacts across the top and bottom (the Lees–Edwards shift matters for these).
        return int(np.sum(np.abs(position[pair[:, 0], 1] - position[pair[:, 1], 1]) > ly / 2))

    def test_shear_run_with_gsd(self):
        self.assertEqual(self.quiet_stderr, "")
        crossing = 0
        with h5py.File(self.shear, "r") as g, gsd.hoomd.open(self.gsd, READ) as f:
            self.assertEqual(len(f), len(SELECTED))
            for frame, k in zip(f, SELECTED):
                with self.subTest(frame=k):
                    self.assertNotEqual(g["lees_edwards/offset/value"][k], 0)  # a tilt to check
                    self.assertGreater(g["contacts/frame_offset"][k + 1] - g["contacts/frame_offset"][k], 0)
                    crossing += self.check_frame(g, frame, k)
        self.assertGreater(crossing, 0, "no contact across the Lees–Edwards boundary: the tilt is not tested")

    def test_shear_run_with_mdanalysis(self):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            u = MDAnalysis.Universe(self.gsd, topology_format="GSD", format="GSD")
        with h5py.File(self.shear, "r") as g, gsd.hoomd.open(self.gsd, READ) as f:
            self.assertEqual(len(u.atoms), len(g["particles/grains/radius"]))
            self.assertEqual(len(u.trajectory), len(SELECTED))
            np.testing.assert_allclose(u.atoms.radii, g["particles/grains/radius"][...], rtol=1e-6)
            for ts, frame, k in zip(u.trajectory, f, SELECTED):
                with self.subTest(frame=k):
                    edges = g["particles/grains/box/edges/value"][k]
                    lx, ly, offset = edges[0, 0], edges[1, 1], edges[1, 0]
                    np.testing.assert_array_equal(ts.positions, frame.particles.position)
                    np.testing.assert_allclose(ts.dimensions[:3], [lx, ly, 1], rtol=1e-6)
                    self.assertAlmostEqual(mda_tilt(ts.dimensions, ly), offset / ly, delta=1e-5)
            # MDAnalysis' bonds are the topology, read from the file's first frame only.
            first, last = g["contacts/frame_offset"][SELECTED[0] : SELECTED[0] + 2]
            pairs = g["contacts/pair"][first:last]
            self.assertGreater(len(pairs), 0)
            self.assertEqual(sorted(map(tuple, u.bonds.indices.tolist())), sorted(map(tuple, pairs.tolist())))
        # A later frame alone: its contacts are MDAnalysis' bonds.
        single = os.path.join(self.out, "single.gsd")
        k = SELECTED[-1]
        result = export(self.shear, "-o", single, "--frames", str(k), "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            u = MDAnalysis.Universe(single, topology_format="GSD", format="GSD")
        with h5py.File(self.shear, "r") as g:
            first, last = g["contacts/frame_offset"][k : k + 2]
            pairs = g["contacts/pair"][first:last]
        self.assertEqual(len(u.bonds), len(pairs))
        self.assertEqual(sorted(map(tuple, u.bonds.indices.tolist())), sorted(map(tuple, pairs.tolist())))

    def test_incline_and_packing(self):
        for path, name in ((self.incline, "incline"), (self.pack, "pack")):
            out = os.path.join(self.out, name + ".gsd")
            result = export(path, "-o", out)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertEqual(len(result.stderr.splitlines()), 1, result.stderr)  # the summary (stderr not a terminal)
            with h5py.File(path, "r") as g, gsd.hoomd.open(out, READ) as f:
                frames = g["particles/grains/position/value"].shape[0]
                self.assertEqual(len(f), frames)
                for k, frame in enumerate(f):
                    with self.subTest(file=name, frame=k):
                        self.check_frame(g, frame, k)
                if name == "incline":
                    self.assertGreater(int(np.sum(f[0].particles.typeid)), 0)  # fixed base grains

    def test_no_contacts(self):
        out = os.path.join(self.out, "grains.gsd")
        result = export(self.shear, "-o", out, "--frames=-3:", "--no-contacts", "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        with h5py.File(self.shear, "r") as g, gsd.hoomd.open(out, READ) as f:
            self.assertEqual(len(f), 3)
            for frame, k in zip(f, range(18, 21)):
                self.check_frame(g, frame, k, contacts=False)
                self.assertNotIn("bonds/normal_force", frame.log)

    def test_bad_input(self):
        bad = os.path.join(self.dir, "bad")
        os.mkdir(bad)
        text = os.path.join(self.dir, "not_hdf5.h5")
        with open(text, "w") as fh:
            fh.write("not an HDF5 file\n")
        cases = {
            "packing: one frame, none in 1:3": ([self.pack, "--frames", "1:3"], "out of range"),
            "frame past the end": ([self.shear, "--frames", "21"], "out of range"),
            "range past the end": ([self.shear, "--frames", "5:99"], "out of range"),
            "empty range": ([self.shear, "--frames", "5:5"], "selects no frame"),
            "malformed range": ([self.shear, "--frames", "a:b"], "option --frames"),
            "step 0": ([self.shear, "--frames", "::0"], "step"),
            "unreadable input": ([text], "not_hdf5.h5"),
            "missing input": ([os.path.join(self.dir, "nothing.h5")], "no such file"),
            "unknown option": ([self.shear, "--colour"], "--colour"),
        }
        for what, (args, words) in cases.items():
            with self.subTest(what):
                out = os.path.join(bad, "out.gsd")
                result = export(*args, "-o", out)
                self.assertEqual(result.returncode, 2, result.stderr)
                lines = result.stderr.splitlines()
                self.assertEqual(len(lines), 1, result.stderr)
                self.assertTrue(lines[0].startswith("granflow export: error: "), lines[0])
                self.assertIn(words, lines[0])
                self.assertEqual(os.listdir(bad), [])  # no output, no temporary
        with self.subTest("output in a missing directory"):
            out = os.path.join(bad, "missing", "out.gsd")
            result = export(self.shear, "-o", out)
            self.assertEqual(result.returncode, 2, result.stderr)
            self.assertEqual(len(result.stderr.splitlines()), 1, result.stderr)
            self.assertIn("does not exist", result.stderr)
            self.assertEqual(os.listdir(bad), [])

    def test_help(self):
        env = dict(os.environ, PYTHONPATH=PYTHONPATH)
        command = [sys.executable, "-m", "granflow", "export", "--help"]
        result = subprocess.run(command, capture_output=True, text=True, env=env)
        self.assertEqual(result.returncode, 0)
        for option in ("--output", "--frames", "--no-contacts", "--quiet", "A:B[:S]"):
            self.assertIn(option, result.stdout)
        result = subprocess.run([sys.executable, "-m", "granflow", "--help"], capture_output=True, text=True, env=env)
        self.assertEqual(result.returncode, 0)
        self.assertIn("export", result.stdout)


def main():
    if MISSING:
        print(f"python.test_export: skipped: gsd or MDAnalysis cannot be imported ({MISSING})", file=sys.stderr)
        return SKIP
    started = time.monotonic()
    suite = unittest.defaultTestLoader.loadTestsFromTestCase(ExportTest)
    result = unittest.TextTestRunner(verbosity=2).run(suite)
    print(f"python.test_export: {time.monotonic() - started:.1f} s", file=sys.stderr)
    return 0 if result.wasSuccessful() else 1


if __name__ == "__main__":
    sys.exit(main())
