#!/usr/bin/env python3
"""ch6_stz.py --figure 6.9|6.10|6.11 INPUT.h5 OUTPUT.png: the STZ figures of thesis §6.3.

6.9:  INPUT = d2min_maps.py's table. Four maps (the table's order: (a) 0 → 0.05, (b) 0.10 → 0.15,
      (c) 0 → 0.15, (d) 0 → −0.05): the grains of each map's reference frame, black where the
      D²min per neighbour exceeds the table's default threshold, grey otherwise, white with an
      outline where the fit was singular; titles with the strains and the black fraction. Beside
      them, against the threshold (log): the Jaccard index of (a) with (b), (c), (d) and its
      chance value for independent sets of the same fractions (dashed), and the black fraction
      of each map; the default threshold marked.
6.10: INPUT = gf-stz fit's table. s/p against γ̇⟨R⟩/√T of the μ = 0 shear runs, one colour per e,
      dense runs filled, dilute ones shaded (pale, open), with the STZ curve (eq. 6.36) of the
      μ = 0 fit (fitted on e = fit_restitution only), drawn from x = 0 (s/p = tanθ*).
6.11: INPUT = gf-stz fit's table. μ = 0 (open) and μ = 0.4 (filled), e = fit_restitution: shear
      runs (circles; dilute ones pale) and incline bulk points (squares), with each μ's curve
      fitted on the shear runs only."""
import argparse
import os
import sys

import numpy as np
from matplotlib.collections import PatchCollection

from analysis import d2min_maps
from granflow import stz_table as st
from granflow.disks import circles, periodic_images
from granflow.plotting import plt, save_figure

GREY, INVALID = "0.82", "white"


def draw_map(ax, maps, k):
    position, radius = maps["position"][k], maps["radius"][k]
    lx, ly = maps["box"][k]
    grain, x, y, _ = periodic_images(position, radius, lx, ly, float(maps["offset"][k]))
    black = maps["black"][k].astype(bool)
    valid = np.isfinite(maps["d2min_scaled"][k])
    colour = np.where(black, "k", np.where(valid, GREY, INVALID))[grain]
    patches = PatchCollection(circles(x, y, radius[grain]), facecolors=colour, edgecolors="0.5", linewidths=0.15)
    ax.add_collection(patches)
    ax.set_xlim(0, lx)
    ax.set_ylim(0, ly)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    fraction = float(np.sum(black)) / max(int(np.sum(valid)), 1)
    ax.set_title(
        f"({maps['label'][k]}) γ {maps['start_strain'][k]:g} → {maps['end_strain'][k]:g}: "
        f"{100 * fraction:.1f} % black",
        fontsize=9,
    )


def figure_6_9(path, output):
    table = d2min_maps.read_table(path)
    maps, sweep, default = table["maps"], table["sweep"], table["default"]
    threshold = default["threshold"]
    count = len(maps["label"])
    fig = plt.figure(figsize=(13, 8))
    grid = fig.add_gridspec(2, 3, width_ratios=(1, 1, 1.1))
    for k in range(min(count, 4)):
        draw_map(fig.add_subplot(grid[k // 2, k % 2]), maps, k)
    t = sweep["threshold"]
    ax = fig.add_subplot(grid[0, 2])
    for p, pair in enumerate(default["pair"]):
        line = ax.semilogx(t, sweep["jaccard"][p], "o-", ms=3, label=f"J({pair})")[0]
        ax.semilogx(t, sweep["jaccard_chance"][p], "--", color=line.get_color(), lw=0.8)
    ax.axvline(threshold, color="0.6", lw=0.8)
    ax.set_xlabel("threshold on D²min per neighbour / ⟨d⟩²")
    ax.set_ylabel("Jaccard index (dashed: chance)")
    ax.set_ylim(0, 1)
    if len(default["pair"]):
        ax.legend(fontsize=8)
    ax = fig.add_subplot(grid[1, 2])
    for k in range(count):
        ax.semilogx(t, sweep["black_fraction"][k], "o-", ms=3, label=f"({maps['label'][k]})")
    ax.axvline(threshold, color="0.6", lw=0.8)
    ax.set_xlabel("threshold on D²min per neighbour / ⟨d⟩²")
    ax.set_ylabel("black fraction")
    ax.set_ylim(0, 1)
    ax.legend(fontsize=8)
    fig.suptitle(
        f"Non-affine grains (D²min per neighbour > {threshold:g} ⟨d⟩²), "
        f"clusters joined within (R_i + R_j)(1 + {float(table['parameters']['gap']):g})",
        fontsize=10,
    )
    save_figure(fig, output)


def points(ax, x, y, xerr, yerr, **style):
    shown = np.isfinite(x) & np.isfinite(y)
    if not np.any(shown):
        return
    ax.errorbar(
        x[shown],
        y[shown],
        xerr=np.where(np.isfinite(xerr[shown]), xerr[shown], 0),
        yerr=np.where(np.isfinite(yerr[shown]), yerr[shown], 0),
        linestyle="none",
        elinewidth=0.7,
        capsize=1.5,
        **style,
    )


def draw_curve(ax, table, friction, x_max, **style):
    row = st.fit_row(table, friction)
    if row is None:
        return False
    x, mu = st.curve(table, row, x_max)
    if len(x):
        ax.plot(x, mu, **style)
    return True


def axes_labels(ax):
    ax.set_xlabel("γ̇⟨R⟩/√T")
    ax.set_ylabel("s/p")


def columns(table):
    get = lambda n: st.column(table, n)  # noqa: E731
    return (
        get("rate_R_over_sqrt_T"),
        get("s_over_p"),
        get("rate_R_over_sqrt_T_error"),
        get("s_over_p_error"),
    )


def figure_6_10(path, output):
    table = st.read_table(path)
    kind, mu, e = st.kinds(table), st.column(table, "friction"), st.column(table, "restitution")
    dense = np.asarray(table["runs"]["dense"]).astype(bool)
    x, y, xe, ye = columns(table)
    shear0 = (kind == "shear") & st.same(mu, 0.0)
    fig, ax = plt.subplots(figsize=(7, 5.2))
    for k, value in enumerate(sorted(set(e[shear0]), reverse=True)):
        colour = f"C{k}"
        rows = shear0 & (np.abs(e - value) < 1e-9)
        # The legend entry goes with the dense points, or with the dilute ones when a restitution
        # has none (e = 0.92 at the quick size), so that every e is named.
        filled = dict(marker="o", color=colour, mfc=colour, ms=5)
        pale = dict(marker="o", color=colour, mfc="none", ms=5, alpha=0.35)
        (filled if np.any(rows & dense) else pale)["label"] = f"e = {value:g}"
        for which, style in ((dense, filled), (~dense, pale)):
            sel = rows & which
            points(ax, x[sel], y[sel], xe[sel], ye[sel], **style)
    x_max = np.nanmax(x[shear0]) if np.any(np.isfinite(x[shear0])) else 1.0
    if draw_curve(ax, table, 0.0, 1.05 * x_max, color="k", lw=1.2, label="STZ, eq. 6.36 (fit)"):
        row = st.fit_row(table, 0.0)
        t = st.column(table, "tan_theta_star", "fit")[row]
        ax.axhline(t, color="0.6", lw=0.7, ls=":")
        ax.set_title(
            f"μ = 0: fitted on e = {st.fit_restitution(table):g}, dense runs "
            f"({table['fit_attrs'].get('dense_rule', 'dense')}); tanθ* = {st.fmt(t)}",
            fontsize=9,
        )
    else:
        ax.set_title("μ = 0: no fit", fontsize=9)
    ax.set_xlim(left=0)
    axes_labels(ax)
    ax.legend(fontsize=8, title="filled: dense, pale: dilute", title_fontsize=8)
    save_figure(fig, output)


def figure_6_11(path, output):
    table = st.read_table(path)
    kind, mu, e = st.kinds(table), st.column(table, "friction"), st.column(table, "restitution")
    x, y, xe, ye = columns(table)
    e_fit = st.fit_restitution(table)
    dense = np.asarray(table["runs"]["dense"]).astype(bool)
    fig, ax = plt.subplots(figsize=(7, 5.2))
    at_e = np.abs(e - e_fit) < 1e-9
    shown = (at_e & (kind == "shear")) | (kind == "incline")
    x_max = np.nanmax(x[shown]) if np.any(np.isfinite(x[shown])) else 1.0
    for k, friction in enumerate((0.0, 0.4)):
        colour = f"C{k}"
        filled = colour if friction > 0 else "none"
        for name, marker, rows, alpha in (
            ("shear", "o", at_e & (kind == "shear") & dense, 1.0),
            (None, "o", at_e & (kind == "shear") & ~dense, 0.35),
            ("incline", "s", kind == "incline", 1.0),
        ):
            sel = rows & st.same(mu, friction)
            label = f"μ = {friction:g}, {name}" if name else None
            points(
                ax,
                x[sel],
                y[sel],
                xe[sel],
                ye[sel],
                marker=marker,
                color=colour,
                mfc=filled,
                ms=5,
                alpha=alpha,
                label=label,
            )
        draw_curve(ax, table, friction, 1.05 * x_max, color=colour, lw=1.2)
    ax.set_xlim(left=0)
    axes_labels(ax)
    ax.set_title(f"e = {e_fit:g}: curves fitted on the shear runs only (eq. 6.36)", fontsize=9)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    save_figure(fig, output)


FIGURES = {"6.9": figure_6_9, "6.10": figure_6_10, "6.11": figure_6_11}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--figure", required=True, choices=sorted(FIGURES))
    ap.add_argument("input")
    ap.add_argument("output")
    args = ap.parse_args()
    if not os.path.exists(args.input):
        sys.exit(f"ch6_stz.py: error: {args.input}: no such file")
    FIGURES[args.figure](args.input, args.output)


if __name__ == "__main__":
    main()
