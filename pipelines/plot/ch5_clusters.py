#!/usr/bin/env python3
"""ch5_clusters.py CLUSTERS.h5 OUTPUT.png: thesis Fig. 5.1, one panel per run of a gf-correlate
file made with --clusters-window (the short branches of ch5.mk): grains that were in contact
during the window are coloured by connected cluster (cluster 1, the largest, first in the
colour cycle), the others are grey. Radii are read from each run (the file's /runs/input)."""
import argparse
import sys

import h5py
import numpy as np
from matplotlib.collections import PatchCollection
from matplotlib.patches import Rectangle

from granflow import correlation_table as ct
from granflow.disks import circles, periodic_images
from granflow.plotting import plt, save_figure


def cluster_colours(labels):
    """RGBA per grain: light grey without contact, else a qualitative colour per cluster."""
    palette = plt.get_cmap("tab20").colors
    rgba = np.tile(np.array([0.88, 0.88, 0.88, 1.0]), (len(labels), 1))
    for i, label in enumerate(labels):
        if label > 0:
            rgba[i, :3] = palette[(label - 1) % len(palette)]
    return rgba


def draw(ax, position, radius, colours, lx, ly, offset):
    grain, x, y, _ = periodic_images(position, radius, lx, ly, offset)
    patches, facecolours = circles(x, y, radius[grain]), colours[grain]
    cells = PatchCollection(patches, facecolors=facecolours, edgecolors="k", linewidths=0.15)
    cells.set_clip_path(Rectangle((0, 0), lx, ly, transform=ax.transData))
    ax.add_collection(cells)
    ax.set_xlim(0, lx)
    ax.set_ylim(0, ly)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("clusters")
    ap.add_argument("output")
    args = ap.parse_args()
    table = ct.read_table(args.clusters)
    if "clusters" not in table:
        sys.exit(f"ch5_clusters.py: {args.clusters} has no /clusters (run gf-correlate with --clusters-window)")
    runs, cl = table["runs"], table["clusters"]
    n = len(runs["input"])
    fig, axes = plt.subplots(1, n, figsize=(5.2 * n, 5.6), squeeze=False)
    for i, ax in enumerate(axes[0]):
        with h5py.File(runs["input"][i], "r") as f:
            radius = f["/particles/grains/radius"][...]
        lo, hi = cl["grain_offset"][i], cl["grain_offset"][i + 1]
        labels, position = cl["label"][lo:hi], cl["position"][lo:hi]
        lx, ly, offset = cl["box"][i]
        draw(ax, position, radius, cluster_colours(labels), lx, ly, offset)
        sizes = np.bincount(labels)[1:]
        steps = int(cl["last_step"][i] - cl["first_step"][i]) + 1
        ax.set_title(
            f"ν = {runs['packing_fraction'][i]:.3f}, e = {runs['restitution'][i]:g}, "
            f"μ = {runs['friction'][i]:g}\n{int(cl['count'][i])} clusters over {steps} steps, "
            f"largest {sizes.max() if len(sizes) else 0} grains, "
            f"{int((labels > 0).sum())}/{len(labels)} grains in contact",
            fontsize=9,
        )
    fig.suptitle(
        f"Thesis Fig. 5.1: grains in contact during a short window, coloured by cluster "
        f"(N = {int(runs['grains'][0])})",
        fontsize=10,
    )
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
