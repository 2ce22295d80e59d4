#!/usr/bin/env python3
"""ch4_snapshot.py RUN.h5 OUTPUT.png [--frame K]: thesis Fig. 4.1, one frame of a simple
shear run with every grain coloured by its lab-frame v_x in units of γ̇L_y/2, in
coordinates centred on the cell as in the thesis (the mean flow is v_x = γ̇y)."""
import argparse
import os

import numpy as np
from matplotlib.collections import PatchCollection
from matplotlib.patches import Rectangle

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
    pos, vel, time, radius = d["position"], d["velocity"], d["time"], d["radius"]
    (lx, _), (offset, ly) = d["edges"]
    rate, nu, e, mu = (float(d["parameters"][k]) for k in ("rate", "packing_fraction", "restitution", "friction"))
    colour = vel[:, 0] / (rate * ly / 2)
    # The image above moves γ̇L_y faster than the grain: its colour is 2 higher.
    grain, x, y, ky = periodic_images(pos, radius, lx, ly, offset)
    patches = circles(x - lx / 2, y - ly / 2, radius[grain])
    values = colour[grain] + 2 * ky
    fig, ax = plt.subplots(figsize=(6.5, 6 * ly / lx))
    cells = PatchCollection(patches, cmap="coolwarm", edgecolors="k", linewidths=0.2)
    cells.set_array(values)
    cells.set_clim(-1.2, 1.2)
    cells.set_clip_path(Rectangle((-lx / 2, -ly / 2), lx, ly, transform=ax.transData))
    ax.add_collection(cells)
    ax.set_xlim(-lx / 2, lx / 2)
    ax.set_ylim(-ly / 2, ly / 2)
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    fig.colorbar(cells, ax=ax, label=r"$v_x / (\dot\gamma L_y/2)$")
    ax.set_title(
        f"Thesis Fig. 4.1: simple shear, N={len(radius)}, ν={nu:.3f}, e={e:g}, μ={mu:g},\n"
        f"γ̇={rate:g}, strain {rate * time:.2f} ({os.path.basename(args.input)})",
        fontsize=9,
    )
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
