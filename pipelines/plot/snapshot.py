#!/usr/bin/env python3
"""snapshot.py INPUT.h5 OUTPUT.png [--frame K]: draw the grains of one frame
(as thesis Fig. 4.1 / 4.7), periodic images across the x boundary included."""
import argparse
import os

from matplotlib.collections import PatchCollection

from granflow.disks import circles, periodic_images
from granflow.hdf5 import read_frame
from granflow.plotting import plt, save_figure


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--frame", type=int, default=-1)
    args = ap.parse_args()
    d = read_frame(args.input, args.frame)
    lx, ly, offset = d["edges"][0][0], d["edges"][1][1], d["edges"][1][0]
    periodic_y = d["fixed"].sum() == 0 and d["position"][:, 1].min() >= 0
    grain, x, y, _ = periodic_images(d["position"], d["radius"], lx, ly if periodic_y else None, offset)
    patches = circles(x, y, d["radius"][grain])
    colors = ["0.35" if fixed else "tab:orange" for fixed in d["fixed"][grain]]
    fig, ax = plt.subplots(figsize=(6, 6 * min(ly / lx, 3)))
    ax.add_collection(PatchCollection(patches, facecolors=colors, edgecolors="k", linewidths=0.3))
    ax.set_xlim(0, lx)
    ax.set_ylim(0 if periodic_y else d["position"][:, 1].min() - d["radius"].max(), ly)
    ax.set_aspect("equal")
    p = d["parameters"]
    ax.set_title(
        f"{os.path.basename(args.input)}: N={len(d['radius'])}"
        + (f", ν={float(p['packing-fraction']):.3f}" if "packing-fraction" in p else "")
    )
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
