#!/usr/bin/env python3
"""ch4_incline_snapshot.py RUN.h5 OUTPUT.png [--frame K]: thesis Fig. 4.7, one frame of a
gf-incline run drawn in the lab frame: the base (fixed grains, filled black) tilted by θ and
gravity vertical, every mobile grain coloured by its velocity down the slope v_x/√(g⟨R⟩).
The run's frame has x along the base (periodic: one period is drawn, grains cut by its ends
drawn whole) and y perpendicular to it; it is rotated by −θ."""
import argparse
import math
import os

import numpy as np
from matplotlib.collections import PatchCollection
from matplotlib.patches import Circle

from granflow.disks import periodic_images
from granflow.hdf5 import in_tau, read_frame
from granflow.plotting import plt, save_figure


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--frame", type=int, default=-1)
    args = ap.parse_args()
    d = read_frame(args.input, args.frame)
    pos, vel, time, radius = d["position"], d["velocity"], d["time"], d["radius"]
    fixed = d["fixed"].astype(bool)
    lx = float(d["edges"][0][0])
    theta, mu, e, tau, gravity, mean_r = (
        float(d["parameters"][k]) for k in ("angle", "friction", "restitution", "tau", "gravity", "mean_radius")
    )
    t = math.radians(theta)
    rot = np.array([[math.cos(t), math.sin(t)], [-math.sin(t), math.cos(t)]])  # R(−θ)
    speed = vel[:, 0] / math.sqrt(gravity * mean_r)
    top = float(np.max(speed[~fixed])) if (~fixed).any() else 1.0
    grain, x, y, _ = periodic_images(pos, radius, lx)  # x periodic, one period drawn
    centres = [rot @ np.array([xi, yi]) for xi, yi in zip(x, y)]
    base = [Circle(c, radius[i]) for c, i in zip(centres, grain) if fixed[i]]
    mobile = [Circle(c, radius[i]) for c, i in zip(centres, grain) if not fixed[i]]
    values = speed[grain[~fixed[grain]]]
    fig, ax = plt.subplots(figsize=(8, 5.5))
    cells = PatchCollection(mobile, cmap="viridis", edgecolors="k", linewidths=0.15)
    cells.set_array(values)
    cells.set_clim(0, top)
    ax.add_collection(cells)
    ax.add_collection(PatchCollection(base, facecolors="k", edgecolors="k"))
    corners = rot @ np.array([[0, lx, lx, 0], [0, 0, pos[:, 1].max(), pos[:, 1].max()]])
    ax.set_xlim(corners[0].min() - 2, corners[0].max() + 2)
    ax.set_ylim(corners[1].min() - 2, corners[1].max() + 4)
    ax.set_aspect("equal")
    ax.annotate(
        "", xy=(0.05, 0.05), xytext=(0.05, 0.25), xycoords="axes fraction", arrowprops={"arrowstyle": "->", "lw": 1.5}
    )
    ax.text(0.07, 0.15, "g", transform=ax.transAxes, ha="left")
    ax.set_xticks([])
    ax.set_yticks([])
    fig.colorbar(cells, ax=ax, shrink=0.7, label=r"$v_x/\sqrt{g\langle R\rangle}$ (down the slope)")
    ax.set_title(
        f"Thesis Fig. 4.7: incline flow, θ = {theta:g}°, μ = {mu:g}, e = {e:g}, "
        f"{int((~fixed).sum())} grains on {int(fixed.sum())} fixed (black),\n"
        f"t = {in_tau(time, d['time_unit'], tau):.0f} τ ({os.path.basename(args.input)})",
        fontsize=9,
    )
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
