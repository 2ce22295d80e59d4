#!/usr/bin/env python3
"""sliding_share.py --steady STEADY.h5 [--margin EPS] --output OUT.h5 RUN.h5:
the share of sliding contacts of a frictional gf-shear run, from its stored frames.

A contact is force-bearing when F_n > 0 and slides when it is at the Coulomb limit,
|F_t| >= (1 - EPS)·μF_n (μ the run's /parameters friction). The solver puts a sliding contact
on the cone's facet exactly: the local solve clamps P_t to ±μP_n and the cluster solves
substitute P_t = ±μP_n (lib/dynamics), so |F_t|/(μF_n) is 1 to rounding (~1e-16) whatever the
tolerance; EPS = 1e-6 (default) is far above that rounding and far below the margin of any
sticking contact that a tolerance could move.

Window: the frames written by the steps of the steady table's window of this run
(steady_state.py's /runs/steady_from, the strain its averages start at; the run is found in the
table by its SHA-256), as gf-network reads them: frames of step > the step of the observable
row before the window. The share is a ratio of means, ⟨sliding⟩/⟨force-bearing⟩ per frame; its
error is the blocking error of its linearisation over the frames.

Output (HDF5, written atomically): /parameters (program, script_sha256, command_line, margin,
steady); /runs/input, input_sha256; /runs/<column> [1]: sliding_share, sliding_share_error,
sliding_contacts, bearing_contacts (means per frame), frames, steady_from, friction (all "1").
Bad input (no such file, not a gf-shear run with contacts, μ <= 0, the run not in the steady
table, fewer than 32 frames in the window, no force-bearing contact): exit 2, one line, no output.
"""
import argparse
import math
import os
import shlex
import sys

import h5py
import numpy as np

from granflow import outputs, statistics
from granflow.hdf5 import read_attrs, read_dataset, sha256, text


class Parser(argparse.ArgumentParser):
    def error(self, message):
        print(f"sliding_share.py: error: {message}", file=sys.stderr)
        sys.exit(2)


def element(f, name):
    """(step, value) of the observable element /observables/<name>."""
    g = f["observables"][name]
    if isinstance(g, h5py.Group):
        return np.asarray(g["step"][()], dtype=np.int64), np.asarray(g["value"][()], dtype=float)
    raise ValueError(f"/observables/{name} is not an H5MD element")


def steady_from(table, digest):
    """The steady_from of the run with SHA-256 `digest` in steady_state.py's table."""
    with h5py.File(table, "r") as f:
        if text(read_attrs(f["parameters"]).get("program", "")) != "steady_state.py":
            raise ValueError(f"{table}: not a steady_state.py table")
        digests = list(read_dataset(f["runs/input_sha256"]))
        if digest not in digests:
            raise ValueError(f"{table}: does not hold the run (no input of its SHA-256)")
        return float(f["runs/steady_from"][digests.index(digest)])


def analyse(run, start, margin):
    """(share, error, mean sliding, mean bearing, frames, μ) over the frames of the window from strain `start`."""
    with h5py.File(run, "r") as f:
        if "contacts" not in f or "observables" not in f:
            raise ValueError(f"{run}: not a gf-shear trajectory with contacts")
        mu = float(read_attrs(f["parameters"])["friction"])
        if not mu > 0:
            raise ValueError(f"{run}: friction {mu:g}: no Coulomb limit")
        row_step, strain = element(f, "strain")
        first = np.flatnonzero(np.abs(strain) >= start)
        if first.size == 0:
            raise ValueError(f"{run}: the window (strain >= {start:g}) starts past the last row")
        before = int(row_step[first[0] - 1]) if first[0] > 0 else 0
        frame_step = f["particles/grains/position/step"][()]
        frames = np.flatnonzero((frame_step > before) & (frame_step <= row_step[-1]))
        if frames.size < statistics.MIN_SAMPLES:
            raise ValueError(f"{run}: {frames.size} frames in the window, at least {statistics.MIN_SAMPLES} needed")
        offset = f["contacts/frame_offset"][()]
        fn_all = f["contacts/normal_force"]
        ft_all = f["contacts/tangential_force"]
        lo, hi = int(offset[frames[0]]), int(offset[frames[-1] + 1])
        fn, ft = fn_all[lo:hi], ft_all[lo:hi]
        sliding = np.empty(frames.size)
        bearing = np.empty(frames.size)
        for k, frame in enumerate(frames):
            a, b = int(offset[frame]) - lo, int(offset[frame + 1]) - lo
            n, t = fn[a:b], ft[a:b]
            on = n > 0
            bearing[k] = np.count_nonzero(on)
            sliding[k] = np.count_nonzero(on & (np.abs(t) >= (1 - margin) * mu * n))
    mean_s, mean_b = sliding.mean(), bearing.mean()
    if not mean_b > 0:
        raise ValueError(f"{run}: no force-bearing contact in the window")
    share = mean_s / mean_b
    # Ratio of means: blocking of share·(s/⟨s⟩ − b/⟨b⟩), or of s/⟨b⟩ when nothing slides.
    linear = share * (sliding / mean_s - bearing / mean_b) if mean_s > 0 else sliding / mean_b
    error = statistics.blocking_error(linear)[0]
    return share, error, mean_s, mean_b, frames.size, mu


def main():
    ap = Parser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steady", required=True, help="steady_state.py's table holding the run (its window)")
    ap.add_argument("--margin", type=float, default=1e-6, help="sliding: |F_t| >= (1 - margin)·μF_n (1e-6)")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("run", help="a frictional gf-shear trajectory with frames")
    args = ap.parse_args()
    if not (0 <= args.margin < 1):
        ap.error(f"--margin {args.margin:g}: must be in [0, 1)")
    for path in (args.steady, args.run):
        if not os.path.isfile(path):
            ap.error(f"{path}: no such file")
    if os.path.abspath(args.output) in (os.path.abspath(args.steady), os.path.abspath(args.run)):
        ap.error(f"{args.output}: the output is also an input")
    try:
        digest = sha256(args.run)
        start = steady_from(args.steady, digest)
        share, error, mean_s, mean_b, frames, mu = analyse(args.run, start, args.margin)
    except (OSError, KeyError, ValueError) as exc:
        ap.error(str(exc).splitlines()[0] if str(exc) else type(exc).__name__)
    parameters = {"margin": args.margin, "steady": args.steady}
    with outputs.table(args.output, os.path.abspath(__file__), shlex.join(sys.argv), parameters,
                       [(args.run, digest)]) as f:
        runs = f["runs"]
        for name, value, meaning in (
            ("sliding_share", share, "sliding over force-bearing contacts per frame (ratio of means)"),
            ("sliding_share_error", error, "blocking error of sliding_share over the frames"),
            ("sliding_contacts", mean_s, f"contacts with F_n > 0 and |F_t| >= (1 - {args.margin:g})·μF_n per frame"),
            ("bearing_contacts", mean_b, "contacts with F_n > 0 per frame"),
            ("frames", frames, "stored frames in the window"),
            ("steady_from", start, "strain the window starts at (the steady table's)"),
            ("friction", mu, "μ, the run's /parameters friction"),
        ):
            outputs.column(runs, name, [value], "1", meaning, dtype=np.int64 if name == "frames" else float)
    return 0


if __name__ == "__main__":
    sys.exit(main())
