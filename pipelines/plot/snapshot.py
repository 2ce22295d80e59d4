#!/usr/bin/env python3
"""snapshot.py INPUT.h5 OUTPUT.png [--frame K]: draw the grains of one frame
(as thesis Fig. 4.1 / 4.7), periodic images across the x boundary included."""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import PatchCollection
from matplotlib.patches import Circle

from granflow_h5 import atomic_output, read_frame


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--frame", type=int, default=-1)
    args = ap.parse_args()
    d = read_frame(args.input, args.frame)
    lx, ly, offset = d["edges"][0][0], d["edges"][1][1], d["edges"][1][0]
    periodic_y = d["fixed"].sum() == 0 and d["position"][:, 1].min() >= 0
    patches, colors = [], []
    for (x, y), r, fixed in zip(d["position"], d["radius"], d["fixed"]):
        # Grains cut by a periodic boundary are drawn on both sides; the images above
        # and below are shifted by the Lees–Edwards offset.
        for ky in ((-1, 0, 1) if periodic_y else (0,)):
            for kx in (-2, -1, 0, 1, 2):
                xs, ys = x + kx * lx + ky * offset, y + ky * ly
                if -r < xs < lx + r and (not periodic_y or -r < ys < ly + r):
                    patches.append(Circle((xs, ys), r))
                    colors.append("0.35" if fixed else "tab:orange")
    fig, ax = plt.subplots(figsize=(6, 6 * min(ly / lx, 3)))
    ax.add_collection(PatchCollection(patches, facecolors=colors, edgecolors="k", linewidths=0.3))
    ax.set_xlim(0, lx)
    ax.set_ylim(0 if periodic_y else d["position"][:, 1].min() - d["radius"].max(), ly)
    ax.set_aspect("equal")
    p = d["parameters"]
    ax.set_title(f"{os.path.basename(args.input)}: N={len(d['radius'])}"
                 + (f", ν={float(p['packing-fraction']):.3f}" if "packing-fraction" in p else ""))
    out = atomic_output(args.output)
    try:
        fig.savefig(out.name, dpi=120, bbox_inches="tight")
        out.commit()
    finally:
        out.abandon()


if __name__ == "__main__":
    main()
