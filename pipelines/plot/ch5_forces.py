#!/usr/bin/env python3
"""ch5_forces.py --figure 5.7|5.8 TABLE.h5 OUTPUT.png: contact-force distributions from
gf-correlate's sweep table, μ = 0. f = F/⟨F⟩ (normal forces), f_bc = F_bc/⟨F_bc⟩ (eq. 5.4, every
contact, zeros included); error bars: jackknife. Labels: ξ_|C|/ξ_el (correlation_table.py) and
gf-correlate's decision "peak at f > 0" or "max at f = 0" with its bootstrap confidence.
Fig. 5.7: P(f) (points) against P(f_bc) (line) for e = E at six ν spread over the sweep.
Fig. 5.8: log P(f), curves offset by factors of 10; left ν ≈ NU for every e, right e = E for
six ν spread over the sweep. Without a run at E, the nearest e of the table is used."""
import argparse
import sys

import numpy as np

from granflow import correlation_table as ct
from granflow.plotting import plt, save_figure


def decision(table, row):
    fo = table["forces"]
    what = "peak at f > 0" if fo["peak"][row] == 1 else "max at f = 0"
    return f"{what} ({100 * fo['peak_confidence'][row]:.0f} %)"


def spread(rows, count):
    """`count` rows evenly spread over `rows` (all of them if fewer)."""
    if len(rows) <= count:
        return list(rows)
    return [rows[i] for i in np.unique(np.round(np.linspace(0, len(rows) - 1, count)).astype(int))]


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--figure", choices=("5.7", "5.8"), required=True)
    ap.add_argument("--restitution", type=float, default=0.75)
    ap.add_argument("--nu", type=float, default=0.7, help="ν of the left panel of Fig. 5.8")
    ap.add_argument("--f-max", type=float, default=4.0)
    ap.add_argument("table")
    ap.add_argument("output")
    args = ap.parse_args()
    table = ct.read_table(args.table)
    res = ct.analyse(table)
    fo, runs = table["forces"], table["runs"]
    f, f_bc = fo["f"], fo["f_bc"]
    shown = f <= args.f_max
    frictionless = np.abs(runs["friction"]) < 1e-9
    if not frictionless.any():
        sys.exit(f"ch5_forces.py: no run with μ = 0 in {args.table}")
    # The e asked for, or the nearest e of the table (small sweeps).
    es = runs["restitution"][frictionless]
    args.restitution = float(es[np.argmin(np.abs(es - args.restitution))])
    rows = ct.select(table, restitution=args.restitution, friction=0.0)
    if args.figure == "5.7":
        chosen = spread(rows, 6)
        fig, axes = plt.subplots(2, 3, figsize=(12, 6.6), squeeze=False)
        for ax, row in zip(axes.ravel(), chosen):
            ax.errorbar(
                f[shown],
                fo["P"][row][shown],
                yerr=fo["P_error"][row][shown],
                fmt="o",
                ms=2.5,
                capsize=1.5,
                label="P(f), contact forces",
            )
            ax.plot(
                f_bc[shown],
                fo["P_bc"][row][shown],
                "-",
                color="tab:red",
                lw=1.2,
                label=r"P($f_{bc}$), binary collisions (5.4)",
            )
            ax.set_title(
                f"ν = {runs['packing_fraction'][row]:.3f}: ξ_|C|/ξ_el = {res['ratio'][row]:.2f} ± "
                f"{res['ratio_error'][row]:.2f}\n{decision(table, row)}",
                fontsize=8,
            )
            ax.set_xlabel("f")
            ax.set_ylabel("P(f)")
            top = np.nanmax(fo["P"][row][shown])
            ax.set_ylim(0, 1.4 * top if np.isfinite(top) and top > 0 else 1)
        for ax in axes.ravel()[len(chosen) :]:
            ax.set_visible(False)
        axes[0, 0].legend(fontsize=7)
        fig.suptitle(
            f"Thesis Fig. 5.7: P(f) against the binary-collision prediction, e = {args.restitution:g}, "
            f"μ = 0 (N = {int(runs['grains'][rows[0]])}; the P(f_bc) spike at f = 0 counts contacts "
            "without approach)",
            fontsize=10,
        )
    else:
        fig, (left, right) = plt.subplots(1, 2, figsize=(12, 7.5))
        nu_rows = []
        for e in np.unique(runs["restitution"][np.abs(runs["friction"]) < 1e-9]):
            row = ct.nearest(table, args.nu, restitution=e, friction=0.0)
            if row is not None:
                nu_rows.append(row)
        for ax, chosen, key in ((left, nu_rows, "e"), (right, spread(rows, 6), "ν")):
            for k, row in enumerate(chosen):
                scale = 10.0**k
                p, err = fo["P"][row][shown] * scale, fo["P_error"][row][shown] * scale
                value = runs["restitution"][row] if key == "e" else runs["packing_fraction"][row]
                mark = "peak at f > 0" if fo["peak"][row] == 1 else "max at f = 0"
                positive = p > 0
                ax.fill_between(
                    f[shown], np.where(p - err > 0, p - err, np.nan), p + err, color=f"C{k}", alpha=0.25, lw=0
                )
                ax.plot(
                    f[shown][positive],
                    p[positive],
                    "o-",
                    ms=2.5,
                    lw=0.7,
                    color=f"C{k}",
                    label=f"{key} = {value:.3g}: ξ_|C|/ξ_el = {res['ratio'][row]:.2f}, {mark}",
                )
            ax.set_yscale("log")
            ax.set_xlabel("f = F/⟨F⟩")
            ax.set_ylabel("P(f) × 10^k (offset)")
            ax.set_xlim(0, args.f_max)
            low, high = ax.get_ylim()
            ax.set_ylim(max(low, high * 1e-9), high * 300)  # room for the legend
            handles, labels = ax.get_legend_handles_labels()
            ax.legend(handles[::-1], labels[::-1], fontsize=7, loc="upper right")
        left.set_title(f"ν ≈ {args.nu:g}, every e", fontsize=9)
        right.set_title(f"e = {args.restitution:g}, six ν spread over the sweep", fontsize=9)
        fig.suptitle(
            "Thesis Fig. 5.8: P(f) at small f; the thesis finds a peak at f > 0 iff ξ/ξ_el < 1.22–1.25 "
            f"(N = {int(runs['grains'][rows[0]])}, μ = 0)",
            fontsize=10,
        )
    fig.tight_layout()
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
