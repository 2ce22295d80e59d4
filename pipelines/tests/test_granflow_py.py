"""The package granflow's modules the pipelines share: the disk images (periodic in x,
Lees–Edwards in y: the image above is shifted by +δ), the table writer's provenance and
atomicity, and strings read back as text whichever way HDF5 stores them."""
import glob
import os
import tempfile
import unittest

import h5py
import numpy as np

from granflow import outputs, units
from granflow.disks import periodic_images
from granflow.hdf5 import read_attrs, read_group, sha256


def images_of(grain, result):
    index, x, y, ky = result
    keep = index == grain
    return sorted(zip(np.round(x[keep], 12), np.round(y[keep], 12), ky[keep]))


class PeriodicImagesTest(unittest.TestCase):
    LX, LY, R = 10.0, 8.0, 0.5

    def test_inner_grain_is_drawn_once(self):
        got = images_of(0, periodic_images([[5.0, 4.0]], [self.R], self.LX, self.LY, 3.0))
        self.assertEqual(got, [(5.0, 4.0, 0)])

    def test_x_boundary_without_periodic_y(self):
        # Cut by x = 0: drawn at x and x + lx; y is left alone even near the edges.
        got = images_of(0, periodic_images([[0.2, 7.9]], [self.R], self.LX))
        self.assertEqual(got, [(0.2, 7.9, 0), (10.2, 7.9, 0)])

    def test_lees_edwards_image_above_is_shifted_by_plus_delta(self):
        delta = 3.0
        # Cut by y = 0: its image one period up is at (x + δ, y + ly).
        got = images_of(0, periodic_images([[4.0, 0.2]], [self.R], self.LX, self.LY, delta))
        self.assertEqual(got, [(4.0, 0.2, 0), (4.0 + delta, 0.2 + self.LY, 1)])
        # Cut by y = ly: its image one period down is at (x − δ, y − ly).
        got = images_of(0, periodic_images([[4.0, 7.9]], [self.R], self.LX, self.LY, delta))
        self.assertEqual(got, [(4.0 - delta, round(7.9 - self.LY, 12), -1), (4.0, 7.9, 0)])

    def test_shift_wraps_through_x(self):
        # δ close to lx: the shifted image is brought back into the cell, two periods if need be.
        delta = 9.9
        got = images_of(0, periodic_images([[9.9, 0.2]], [self.R], self.LX, self.LY, delta))
        self.assertIn((round(9.9 + delta - 2 * self.LX, 12), 0.2 + self.LY, 1), got)

    def test_corner_grain_has_four_images(self):
        got = images_of(0, periodic_images([[0.1, 0.1]], [self.R], self.LX, self.LY, 0.0))
        self.assertEqual(len(got), 4)


class TableTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.d = self.tmp.name
        self.script = os.path.join(self.d, "maker.py")
        with open(self.script, "w") as fh:
            fh.write("# a table script\n")

    def tearDown(self):
        self.tmp.cleanup()

    def test_provenance_and_inputs(self):
        out = os.path.join(self.d, "table.h5")
        with outputs.table(
            out, self.script, "maker.py -o table.h5 a.h5", {"window": 2.5}, [("a.h5", "00ff"), ("b.h5", "ff00")]
        ) as f:
            outputs.column(f["runs"], "x", [1.0, 2.0], "L T-1", "a velocity")
        table = outputs.read_table(out, ("runs",))
        self.assertEqual(
            table["parameters"],
            {
                "program": "maker.py",
                "script_sha256": sha256(self.script),
                "command_line": "maker.py -o table.h5 a.h5",
                "window": 2.5,
            },
        )
        self.assertEqual(list(table["runs"]["input"]), ["a.h5", "b.h5"])
        self.assertEqual(list(table["runs"]["input_sha256"]), ["00ff", "ff00"])
        np.testing.assert_array_equal(table["runs"]["x"], [1.0, 2.0])

    def test_nothing_written_on_failure(self):
        out = os.path.join(self.d, "table.h5")
        with self.assertRaises(RuntimeError):
            with outputs.table(out, self.script, "", {}, []):
                raise RuntimeError("analysis failed")
        self.assertEqual(os.listdir(self.d), ["maker.py"])
        self.assertEqual(glob.glob(os.path.join(self.d, ".*")), [])

    def test_units_as_h5md_asks(self):
        out = os.path.join(self.d, "table.h5")
        with outputs.table(out, self.script, "", {}, []) as f:
            outputs.column(f["runs"], "x", [1.0, 2.0], "M T-2", "a 2D stress")
            outputs.column_group(f, "long", {"name": ["p", "a0"], "unit": ["M T-2", "rad"], "value": [3.0, 0.5],
                                             "step": [1e-3, 1e-3]}, {"value": "unit", "step": "1"})
        with h5py.File(out, "r") as f:
            x = f["runs/x"]
            kind = x.attrs.get_id("unit").get_type()
            self.assertFalse(kind.is_variable_str())
            self.assertEqual(kind.get_cset(), h5py.h5t.CSET_ASCII)
            self.assertEqual(x.attrs["unit"], b"M T-2")
            self.assertEqual(f["long/value"].attrs[units.ROW_UNIT], "unit")
            self.assertNotIn("unit", f["long/value"].attrs)
            self.assertEqual(f["long/step"].attrs["unit"], b"1")
            self.assertEqual(units.table_problems(f), [])

    def test_no_table_with_a_number_without_a_valid_unit(self):
        out = os.path.join(self.d, "table.h5")
        for name, write in (
            ("no unit", lambda f: f["runs"].create_dataset("x", data=[1.0])),
            ("misspelt", lambda f: f["runs"].create_dataset("x", data=[1.0]).attrs.create("unit", np.bytes_(b"Lx"))),
            ("variable-length", lambda f: f["runs"].create_dataset("x", data=[1.0]).attrs.update({"unit": "L"})),
            ("bad row unit", lambda f: outputs.column_group(f, "long", {"unit": ["L", "m"], "value": [1.0, 2.0]},
                                                            {"value": "unit"})),
        ):
            with self.subTest(name):
                with self.assertRaisesRegex(ValueError, "without a valid unit: /"):
                    with outputs.table(out, self.script, "", {}, []) as f:
                        write(f)
                self.assertEqual(sorted(os.listdir(self.d)), ["maker.py"])
        with self.assertRaisesRegex(ValueError, "unknown symbol 'K'"):
            with outputs.table(out, self.script, "", {}, []) as f:
                outputs.column(f["runs"], "x", [1.0], "K", "a temperature in kelvin")


class UnitsTest(unittest.TestCase):
    def test_grammar(self):
        for good in ("1", "L", "L T-1", "M L+2 T-2", "0.5 L", "1.4 L", "tau-1", "rad", "deg", "2+3 L"):
            self.assertIsNone(units.problem(good), good)
        for bad in ("", "L  T", "T L T", "L T1", "L T+0", "L 2", "m", "L^2", "velocity", None):
            self.assertIsNotNone(units.problem(bad), bad)

    def test_times_power(self):
        self.assertEqual(units.times_power("T-1", "T", 1), "1")
        self.assertEqual(units.times_power("L", "T", -1), "L T-1")
        self.assertEqual(units.times_power("1", "T", 2), "T+2")
        self.assertEqual(units.times_power("M T-2", "T", 2), "M")
        self.assertEqual(units.times_power("0.5 L T-1", "T", 1), "0.5 L")
        with self.assertRaises(ValueError):
            units.times_power("velocity", "T", 1)


class TextTest(unittest.TestCase):
    def test_strings_come_back_as_text(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "s.h5")
            with h5py.File(path, "w") as f:
                g = f.create_group("g")
                g["fixed"] = np.array([b"a.h5", b"bb.h5"])  # as the C++ programs write them
                g["variable"] = np.array(["a.h5", "bb.h5"], dtype=h5py.string_dtype())
                g["number"] = np.arange(2)
                g.attrs["note"] = np.bytes_("x")
            with h5py.File(path, "r") as f:
                got = read_group(f["g"])
                self.assertEqual(read_attrs(f["g"]), {"note": "x"})
        self.assertEqual(list(got["fixed"]), ["a.h5", "bb.h5"])
        self.assertEqual(list(got["variable"]), ["a.h5", "bb.h5"])
        np.testing.assert_array_equal(got["number"], [0, 1])


if __name__ == "__main__":
    unittest.main()
