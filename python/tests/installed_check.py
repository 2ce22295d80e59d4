"""installed_check.py VENV RUNS_DIR: run by test_install.py with the Python of a fresh venv in
which `pip install` put the package granflow, in isolated mode (-I: no PYTHONPATH, no script
directory on sys.path) from a directory outside the repository. Checks that granflow comes
from the venv with its own statistics library, then reads RUNS_DIR/shear.h5 frame by frame
against h5py, RUNS_DIR/kinetic.h5 (gf-kinetic's table of it) and computes the blocking error of
RUNS_DIR/series.npy, which must equal RUNS_DIR/series_blocking.txt (the CMake build's library). Prints one line per check; exits 1 at the first failure."""
import math
import os
import sys

import h5py
import numpy as np


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)
    print(f"ok: {message}")


def main():
    venv, runs = (os.path.realpath(a) for a in sys.argv[1:3])
    import granflow
    import granflow.statistics as st

    package = os.path.dirname(os.path.realpath(granflow.__file__))
    check(package.startswith(venv + os.sep), f"granflow imported from the venv ({package})")
    check(os.environ.get("GRANFLOW_BUILD") is None, "no GRANFLOW_BUILD")
    library = st.library_path()
    check(
        library == os.path.join(package, st.LIBRARY_NAME) and os.path.isfile(library),
        f"the package's own statistics library {library}",
    )

    shear = os.path.join(runs, "shear.h5")
    frames = 0
    with granflow.Trajectory(shear) as run, h5py.File(shear, "r") as f:
        g = f["particles/grains"]
        np.testing.assert_array_equal(run.radius, g["radius"][...])
        for k, frame in enumerate(run):
            np.testing.assert_array_equal(frame.position, g["position/value"][k])
            np.testing.assert_array_equal(frame.velocity, g["velocity/value"][k])
            np.testing.assert_array_equal(frame.angular_velocity, g["angular_velocity/value"][k])
            edges = g["box/edges/value"][k]
            if (frame.box.lx, frame.box.ly, frame.box.offset) != (edges[0][0], edges[1][1], edges[1][0]):
                fail(f"frame {k}: box {frame.box} against edges {edges.tolist()}")
            if frame.box.offset != f["lees_edwards/offset/value"][k]:
                fail(f"frame {k}: offset {frame.box.offset} against /lees_edwards {f['lees_edwards/offset/value'][k]}")
            first, last = f["contacts/frame_offset"][k : k + 2]
            np.testing.assert_array_equal(frame.contacts.pair, f["contacts/pair"][first:last])
            np.testing.assert_array_equal(frame.contacts.normal_force, f["contacts/normal_force"][first:last])
            frames += 1
        check(frames == len(g["position/value"]) > 1, f"{frames} frames of {shear}: grains, box and contacts as h5py")

    kinetic = granflow.read_table(os.path.join(runs, "kinetic.h5"))
    with h5py.File(os.path.join(runs, "kinetic.h5"), "r") as f:
        for name, column in kinetic["runs"].columns().items():
            if column.values.dtype.kind == "f":
                np.testing.assert_array_equal(column.values, f["runs"][name][...])
        p, units = kinetic["runs/p_static"], f["runs/p_static"].attrs["units"]
        check(
            kinetic.kind == "gf-kinetic" and p.units == getattr(units, "decode", lambda: units)() and p.meaning,
            f"gf-kinetic table: p_static = {p.values[0]:.6g} [{p.units}]",
        )

    x = np.load(os.path.join(runs, "series.npy"))
    with open(os.path.join(runs, "series_blocking.txt")) as fh:
        error, blocks, plateau = fh.read().split()
    expected = (float(error), int(blocks), bool(int(plateau)))
    got = st.blocking_error(x)
    check(got == expected, f"blocking error {got} equals the CMake build's {expected}")
    rng = np.random.default_rng(46)
    blocks = np.column_stack((rng.normal(size=40), np.ones(40)))
    jackknife = st.jackknife_errors(blocks, lambda s: [s[0] / s[1]])[0]
    check(abs(jackknife / (np.std(blocks[:, 0], ddof=1) / math.sqrt(40)) - 1) < 1e-12, f"jackknife error {jackknife}")
    print("installed_check.py: all checks passed")


if __name__ == "__main__":
    main()
