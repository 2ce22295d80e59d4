"""The synthetic gf-correlate tables of the chapter-5 tests (synthetic.write_correlate_table,
write_clusters_table) against the real program's output: gf-pack → gf-shear → gf-correlate on
64 grains (GRANFLOW_BIN; seconds), the sweep with --reference and a --clusters-window table as
ch5.mk makes them. Every dataset of the synthetic tables must be in the real output with the
same rank and kind of dtype, every attribute too; and every dataset and attribute the chapter-5
scripts read (recorded while the figure scripts and the report run on the synthetic tables)
must be in both. So a fixture that drifts from gf-correlate, or a gf-correlate that renames or
drops what the scripts read, fails here, not in a figure made from real runs."""
import os
import runpy
import subprocess
import sys
import tempfile
import unittest
from unittest import mock

import h5py

from granflow import correlation_table as ct
from report import ch5

import synthetic  # a sibling module: the tests' own fixtures

BIN = os.environ.get("GRANFLOW_BIN", "")
PROGRAMS = ("gf-pack", "gf-shear", "gf-correlate")
PIPELINES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def schema(path):
    """{dataset path: (rank, dtype kind)} and {group or dataset path: set of attribute names}."""
    datasets, attrs = {}, {"": set()}
    with h5py.File(path, "r") as f:
        attrs[""] = set(f.attrs)

        def visit(name, obj):
            attrs[name] = set(obj.attrs)
            if isinstance(obj, h5py.Dataset):
                datasets[name] = (obj.ndim, obj.dtype.kind)

        f.visititems(visit)
    return datasets, attrs


class _Recorder(dict):
    """A dict of read_table()'s result that logs every key looked up or tested for."""

    def __init__(self, content, where, log):
        super().__init__(content)
        self._where, self._log = where, log

    def _note(self, key):
        if key != "attrs":
            self._log.add(self._where + (key,))

    def __getitem__(self, key):
        self._note(key)
        return super().__getitem__(key)

    def get(self, key, default=None):
        self._note(key)
        return super().get(key, default)

    def __contains__(self, key):
        self._note(key)
        return super().__contains__(key)


def recording_reader(log, read_table):
    """ct.read_table that logs (path, group, "dataset" or "attribute", name) for every lookup."""

    def read(path):
        table = read_table(path)
        for group, content in list(table.items()):
            if group == "parameters":
                table[group] = _Recorder(content, (path, group, "attribute"), log)
            elif isinstance(content, dict):
                if "attrs" in content:
                    content["attrs"] = _Recorder(content["attrs"], (path, group, "attribute"), log)
                table[group] = _Recorder(content, (path, group, "dataset"), log)
        return table

    return read


@unittest.skipUnless(
    all(os.path.isfile(os.path.join(BIN, p)) for p in PROGRAMS),
    "GRANFLOW_BIN (the built gf-* programs) not given; ctest sets it",
)
class CorrelateSchemaTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = cls.tmp.name

        def run(program, *args):
            subprocess.run([os.path.join(BIN, program), "--quiet", *args], check=True, cwd=d)

        shear = []
        for nu, e in (("0.5", "0.92"), ("0.7", "0")):
            run("gf-pack", "--grains", "64", "--packing-fraction", nu, "--seed", "1", "-o", f"pack{nu}.h5")
            run(
                "gf-shear",
                "-i",
                f"pack{nu}.h5",
                "-o",
                f"shear{nu}.h5",
                "--rate",
                "1e-2",
                "--restitution",
                e,
                "--friction",
                "0",
                "--seed",
                "1",
                "--strain",
                "0.2",
                "--strain-step",
                "1e-3",
                "--frame-every",
                "10",
            )
            shear.append(f"shear{nu}.h5")
        run(
            "gf-correlate",
            "-o",
            "correlate.h5",
            "--from-strain",
            "0.05",
            "--detect-transient",
            "--reference",
            shear[0],
            *shear,
        )
        run(
            "gf-shear",
            "-i",
            shear[1],
            "--frame",
            "-1",
            "-o",
            "window.h5",
            "--rate",
            "1e-2",
            "--restitution",
            "0",
            "--friction",
            "0",
            "--seed",
            "1",
            "--steps",
            "10",
            "--strain-step",
            "1e-3",
            "--frame-every",
            "1",
        )
        run(
            "gf-correlate",
            "-o",
            "clusters.h5",
            "--from-strain",
            "0",
            "--blocks",
            "1",
            "--bootstrap",
            "0",
            "--clusters-window",
            "10",
            "window.h5",
        )
        cls.synthetic = synthetic.chapter5_tables(d)
        # Each synthetic table and the real output it stands for.
        cls.real = {
            cls.synthetic["table"]: os.path.join(d, "correlate.h5"),
            cls.synthetic["clusters"]: os.path.join(d, "clusters.h5"),
        }

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_fixture_datasets_and_attributes_are_the_programs(self):
        for fake, real in self.real.items():
            fake_sets, fake_attrs = schema(fake)
            real_sets, real_attrs = schema(real)
            for name, (rank, kind) in fake_sets.items():
                with self.subTest(table=os.path.basename(fake), dataset=name):
                    self.assertTrue(name in real_sets, "the fixture writes a dataset gf-correlate does not")
                    self.assertEqual(real_sets[name][0], rank, "rank")
                    self.assertEqual(real_sets[name][1], kind, "dtype kind")
            for name, attrs in fake_attrs.items():
                with self.subTest(table=os.path.basename(fake), attributes_of=name or "/"):
                    self.assertLessEqual(
                        attrs, real_attrs.get(name, set()), "the fixture writes attributes gf-correlate does not"
                    )

    def test_what_the_scripts_read_is_in_both(self):
        log = set()
        table, clusters = self.synthetic["table"], self.synthetic["clusters"]
        out = os.path.join(self.tmp.name, "figure.png")
        commands = [
            ("ch5_clusters.py", clusters),
            ("ch5_correlation.py", table),
            ("ch5_xi.py", "--vary", "restitution", table),
            ("ch5_xi.py", "--vary", "friction", "--restitution", "0", table),
            ("ch5_anisotropy.py", "--figure", "5.5", table),
            ("ch5_anisotropy.py", "--figure", "5.6", table),
            ("ch5_forces.py", "--figure", "5.7", table),
            ("ch5_forces.py", "--figure", "5.8", table),
            ("ch5_phase.py", "--figure", "5.9", table),
            ("ch5_phase.py", "--figure", "5.10", table),
        ]
        with mock.patch.object(ct, "read_table", recording_reader(log, ct.read_table)):
            for script, *args in commands:
                with self.subTest(script=script, args=args), mock.patch.object(sys, "argv", [script, *args, out]):
                    runpy.run_path(os.path.join(PIPELINES, "plot", script), run_name="__main__")
            ch5.section(table, clusters)
        self.assertTrue(any(kind == "dataset" for _, _, kind, _ in log), "nothing was recorded")
        for path, group, kind, name in sorted(log):
            for label, target in (("synthetic", path), ("gf-correlate", self.real[path])):
                with self.subTest(read=f"{group}/{name} ({kind})", table=label):
                    datasets, attrs = schema(target)
                    if kind == "dataset":
                        self.assertTrue(f"{group}/{name}" in datasets, f"no dataset /{group}/{name}")
                    else:
                        self.assertTrue(name in attrs.get(group, set()), f"no attribute {name} of /{group}")


if __name__ == "__main__":
    unittest.main()
