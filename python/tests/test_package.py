"""The package granflow's reading API against plain h5py reads of the same files, made by the
built programs (GRANFLOW_BIN; 64 grains, well under a second each): granflow.Trajectory frame
by frame (grains, the Lees–Edwards box, every contact column), granflow.hdf5.read_frame
(the pipelines' snapshot reader, now on top of it) against its former implementation,
granflow.read_table on the tables of gf-kinetic, gf-correlate, gf-network, gf-stz fit and
d2min and steady_state.py (every dataset, its unit, units and meaning), and the example
examples/pressure_vs_packing.py on a steady_state.py table of real runs. Run from the
repository (PYTHONPATH=<repo>/python:<repo>/pipelines)."""
import os
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

import granflow
from granflow import hdf5

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import programs  # noqa: E402  (a sibling module: the tests' inputs)

EXAMPLE = os.path.join(programs.REPO, "python", "examples", "pressure_vs_packing.py")
STEADY_STATE = os.path.join(programs.REPO, "pipelines", "analysis", "steady_state.py")


def old_read_frame(path, frame=-1):
    """granflow.hdf5.read_frame as it was before it read through granflow.Trajectory."""
    with h5py.File(path, "r") as f:
        g = f["/particles/grains"]
        return {
            "position": g["position/value"][frame],
            "velocity": g["velocity/value"][frame],
            "time": float(g["position/time"][frame]),
            "time_unit": hdf5.time_unit(g["position/time"]),
            "radius": g["radius"][...],
            "fixed": g["fixed"][...] if "fixed" in g else np.zeros(len(g["radius"]), dtype=np.uint8),
            "edges": g["box/edges/value"][frame],
            "parameters": hdf5.read_attrs(f["/parameters"]),
        }


class Runs:
    """The inputs, made once per test class in a temporary directory."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = cls.tmp.name
        cls.make()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()


@programs.require("gf-pack", "gf-shear", "gf-incline")
class TrajectoryTest(Runs, unittest.TestCase):
    @classmethod
    def make(cls):
        cls.shear = programs.shear_run(cls.dir)
        cls.pack = os.path.join(cls.dir, "pack_nu0.800.h5")
        cls.incline_pack, cls.incline = programs.incline_run(cls.dir)

    def check_against_h5py(self, path):
        with h5py.File(path, "r") as f, granflow.Trajectory(path) as run:
            g = f["particles/grains"]
            frames = g["position/value"].shape[0]
            self.assertEqual(len(run), frames)
            np.testing.assert_array_equal(run.radius, g["radius"][...])
            np.testing.assert_array_equal(run.mass, g["mass"][...])
            np.testing.assert_array_equal(run.fixed, g["fixed"][...])
            np.testing.assert_array_equal(run.steps, g["position/step"][...])
            np.testing.assert_array_equal(run.times, g["position/time"][...])
            self.assertEqual(run.parameters, hdf5.read_attrs(f["parameters"]))
            seen = 0
            for k, frame in enumerate(run):  # one frame at a time
                self.assertEqual(frame.index, k)
                self.assertEqual(frame.step, g["position/step"][k])
                self.assertEqual(frame.time, g["position/time"][k])
                for name in ("position", "velocity", "orientation", "angular_velocity"):
                    np.testing.assert_array_equal(getattr(frame, name), g[name + "/value"][k], err_msg=name)
                edges = g["box/edges/value"][k]
                np.testing.assert_array_equal(frame.box.edges, edges)
                box = frame.box
                self.assertEqual((box.lx, box.ly, box.offset), (edges[0][0], edges[1][1], edges[1][0]))
                if "lees_edwards" in f:
                    self.assertEqual(frame.box.offset, f["lees_edwards/offset/value"][k])
                    self.assertEqual(frame.box.rate, f["lees_edwards"].attrs["rate"])
                if "contacts" in f:
                    first, last = f["contacts/frame_offset"][k : k + 2]
                    names = sorted(n for n in f["contacts"] if n != "frame_offset")
                    self.assertEqual(sorted(frame.contacts.columns), names)
                    for name in names:
                        np.testing.assert_array_equal(
                            frame.contacts.columns[name], f["contacts"][name][first:last], err_msg=name
                        )
                    seen += last - first
            if "contacts" in f:
                self.assertEqual(seen, f["contacts/frame_offset"][frames])
            return seen

    def test_shear_run_frame_by_frame(self):
        contacts = self.check_against_h5py(self.shear)
        self.assertGreater(contacts, 0, "a run at ν = 0.8 has contacts")
        with granflow.Trajectory(self.shear) as run:
            self.assertEqual((run.time_unit, run.periodic, run.rate), ("T", (True, True), 1.0))
            last = run[-1]
            self.assertEqual(last.index, len(run) - 1)
            self.assertGreater(last.box.offset, 0)
            self.assertIsNone(run.frame(2, contacts=False).contacts)
            with self.assertRaises(IndexError):
                run[len(run)]

    def test_contact_forces(self):
        with granflow.Trajectory(self.shear) as run:
            frame = max(run, key=lambda fr: len(fr.contacts))
        c = frame.contacts
        self.assertEqual(c.pair.shape, (len(c), 2))
        n = c.branch / np.hypot(c.branch[:, 0], c.branch[:, 1])[:, None]
        expected = c.normal_force[:, None] * n + c.tangential_force[:, None] * np.column_stack((-n[:, 1], n[:, 0]))
        np.testing.assert_allclose(c.force(), expected, rtol=1e-15, atol=0)
        self.assertTrue((c.pair[:, 0] < c.pair[:, 1]).all())

    def test_packing_has_empty_contacts(self):
        self.check_against_h5py(self.pack)
        with granflow.Trajectory(self.pack) as run:
            self.assertFalse(run.has_contacts)
            c = run[0].contacts
        self.assertEqual(len(c), 0)
        self.assertEqual(c.pair.shape, (0, 2))
        self.assertEqual(c.force().shape, (0, 2))

    def test_incline(self):
        self.check_against_h5py(self.incline)
        with granflow.Trajectory(self.incline) as run:
            self.assertEqual((run.time_unit, run.periodic, run.rate), ("tau", (True, False), None))
            self.assertGreater(int(run.fixed.sum()), 0)
            self.assertEqual(run[0].box.offset, 0.0)

    def test_read_frame_as_before(self):
        for path in (self.shear, self.pack, self.incline):
            for frame in (-1, 0, 1) if path != self.pack else (-1, 0):
                with self.subTest(path=os.path.basename(path), frame=frame):
                    new, old = hdf5.read_frame(path, frame), old_read_frame(path, frame)
                    self.assertEqual(sorted(new), sorted(old))
                    for key, value in old.items():
                        if isinstance(value, np.ndarray):
                            self.assertEqual(new[key].dtype, value.dtype, key)
                            np.testing.assert_array_equal(new[key], value, err_msg=key)
                        else:
                            self.assertEqual(new[key], value, key)

    def test_not_a_trajectory(self):
        path = os.path.join(self.dir, "table.h5")
        with h5py.File(path, "w") as f:
            f.create_group("runs")
        with self.assertRaisesRegex(ValueError, "not a granflow trajectory"):
            granflow.Trajectory(path)


@programs.require("gf-pack", "gf-shear", "gf-kinetic", "gf-correlate", "gf-network", "gf-stz")
class TablesTest(Runs, unittest.TestCase):
    @classmethod
    def make(cls):
        cls.runs = [programs.shear_run(cls.dir, nu, restitution=0.0) for nu in (0.70, 0.75, 0.80, 0.82)]
        cls.tables = {
            "gf-kinetic": programs.kinetic_table(cls.dir, cls.runs),
            "gf-correlate": programs.correlate_table(cls.dir, cls.runs),
        }
        for kind, args in (
            ("gf-network", ("gf-network", "--from-strain", "0.1", *cls.runs[2:])),
            ("gf-stz fit", ("gf-stz fit", "--min-packing-fraction", "0.7", "--from-strain", "0.1", *cls.runs)),
            ("gf-stz d2min", ("gf-stz d2min", "--frames", "5,10", "-i", cls.runs[2])),
        ):
            cls.tables[kind] = os.path.join(cls.dir, kind.replace(" ", "_") + ".h5")
            programs.run(*args, "-o", cls.tables[kind])
        cls.tables["steady_state.py"] = os.path.join(cls.dir, "steady.h5")
        subprocess.run(
            [sys.executable, STEADY_STATE, "--from-strain", "0.1", "-o", cls.tables["steady_state.py"], *cls.runs],
            check=True,
            capture_output=True,
        )

    def test_every_dataset_with_units_and_meaning(self):
        for kind, path in self.tables.items():
            with self.subTest(kind=kind):
                table = granflow.read_table(path)
                self.assertEqual(table.kind, kind)
                self.assertEqual(table.path, path)
                with h5py.File(path, "r") as f:
                    self.assertEqual(table.parameters, hdf5.read_attrs(f["parameters"]))
                    datasets = []
                    f.visititems(lambda name, obj: datasets.append(name) if isinstance(obj, h5py.Dataset) else None)
                    self.assertEqual(sorted(c.name for c in table.walk()), sorted(datasets))
                    described = table.describe().splitlines()
                    self.assertEqual(len(described), len(datasets))
                    for name in datasets:
                        column, ds = table[name], f[name]
                        np.testing.assert_array_equal(column.values, hdf5.read_dataset(ds), err_msg=name)
                        np.testing.assert_array_equal(np.asarray(column), column.values)
                        self.assertEqual(column.units, hdf5.read_attrs(ds).get("units"), name)
                        self.assertEqual(column.unit, hdf5.read_attrs(ds).get("unit"), name)
                        self.assertEqual(column.meaning, hdf5.read_attrs(ds).get("meaning"), name)
                        self.assertTrue(any(line.startswith(name + " ") for line in described), name)
                        # Every table gives every number a unit; the programs' tables every
                        # dataset a meaning and every number its unit in words too.
                        if column.values.dtype.kind in "iuf":
                            self.assertIsNotNone(column.unit, name)
                            self.assertIn(f"[{column.unit}]", next(l for l in described if l.startswith(name + " ")))
                        if kind.startswith("gf-"):
                            self.assertIsNotNone(column.meaning, name)
                            if column.values.dtype.kind in "iuf":
                                self.assertIsNotNone(column.units, name)
                    for name, group in f.items():
                        if isinstance(group, h5py.Group):
                            attrs = hdf5.read_attrs(group)
                            self.assertEqual(sorted(table[name].attrs), sorted(attrs))
                            for key, value in attrs.items():
                                np.testing.assert_array_equal(table[name].attrs[key], value)

    def test_lookups(self):
        table = granflow.read_table(self.tables["gf-kinetic"])
        runs = table["runs"]
        self.assertIs(table["runs/p_static"], runs["p_static"])
        self.assertIn("runs/p_static", table)
        self.assertEqual(runs["p_static"].units, "mass/time^2")
        self.assertEqual(runs["p_static"].unit, "M T-2")
        self.assertEqual(list(runs["input"].values), self.runs)
        self.assertEqual(set(runs.arrays()), set(runs.columns()))
        with self.assertRaisesRegex(KeyError, "/runs has no 'nothing'"):
            table["runs/nothing"]

    def test_pipelines_readers_agree(self):
        # granflow.kinetic_table and correlation_table (the figures' readers) read the same values.
        from granflow import correlation_table, kinetic_table

        for module, kind in ((kinetic_table, "gf-kinetic"), (correlation_table, "gf-correlate")):
            old, new = module.read_table(self.tables[kind]), granflow.read_table(self.tables[kind])
            for name, values in old["runs"].items():
                if name != "attrs":
                    np.testing.assert_array_equal(new["runs"][name].values, values, err_msg=name)


@programs.require("gf-pack", "gf-shear")
class ExampleTest(Runs, unittest.TestCase):
    """examples/pressure_vs_packing.py on a steady_state.py table of three e = 0 runs and one
    e = 0.5 run at another rate: the points it plots are p/γ̇² of the table's rows."""

    @classmethod
    def make(cls):
        runs = [programs.shear_run(cls.dir, nu, restitution=0.0) for nu in (0.70, 0.75, 0.80)]
        runs.append(programs.shear_run(cls.dir, 0.75, restitution=0.5, rate=2.0))
        cls.table = os.path.join(cls.dir, "ch4_sweep.h5")
        subprocess.run(
            [sys.executable, STEADY_STATE, "--from-strain", "0.1", "-o", cls.table, *runs],
            check=True,
            capture_output=True,
        )

    def test_docs_quote_the_script(self):
        with open(EXAMPLE, encoding="utf-8") as f:
            script = f.read()
        with open(os.path.join(programs.REPO, "docs", "python.md"), encoding="utf-8") as f:
            self.assertIn("```python\n" + script + "```\n", f.read())

    def test_plot_of_pressure_over_rate_squared(self):
        png = os.path.join(self.dir, "p.png")
        result = subprocess.run([sys.executable, EXAMPLE, self.table, png], capture_output=True, text=True)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(png, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
        with h5py.File(self.table, "r") as f:
            nu, e = f["runs/packing_fraction"][...], f["runs/restitution"][...]
            expected = f["steady/pressure"][...] / f["runs/rate"][...] ** 2
        printed = [line.split() for line in result.stdout.splitlines() if line.startswith("e =")]
        self.assertEqual(len(printed), len(nu), result.stdout)
        rows = []
        for fields in printed:  # "e = 0  ν = 0.7000  p/γ̇² = 3.23631 ± 0.91"
            rows.append(int(np.flatnonzero((e == float(fields[2])) & np.isclose(nu, float(fields[5]), atol=5e-5))[0]))
            self.assertAlmostEqual(float(fields[8]) / expected[rows[-1]], 1, delta=1e-5)
        self.assertEqual(sorted(rows), list(range(len(nu))))
        self.assertIn("[M T-2]; γ̇ in [T-1]", result.stdout)  # the units the table gives


if __name__ == "__main__":
    unittest.main()
