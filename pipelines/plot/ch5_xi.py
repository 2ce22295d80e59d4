#!/usr/bin/env python3
"""ch5_xi.py --vary restitution|friction [--restitution E] TABLE.h5 OUTPUT.png: thesis Fig. 5.3
(ξ against ν for every e at μ = 0, inset: the dense end) or Fig. 5.4 (--vary friction: every μ
at e = E). ξ is gf-correlate's ξ_|C| (/correlation/xi_abs, the decay length of |C̄|) in mean
diameters σ, error bars its block-jackknife errors; the dashed line is ξ_el (/correlation/
xi_abs_el, the reference runs) and the dotted one 1.25 ξ_el. Hollow markers: runs that
gf-correlate flags as not measurable (/correlation/measurable: correlations reach the box, so
ξ_|C| measures the cell rather than the network, the thesis' "too large to be measured")."""
import argparse
import sys

import numpy as np

from granflow import correlation_table as ct
from granflow.plotting import plt, save_figure


def series(table, vary, restitution):
    runs = table["runs"]
    if vary == "restitution":
        return [
            (f"e = {e:g}", dict(restitution=e, friction=0.0))
            for e in np.unique(runs["restitution"][np.abs(runs["friction"]) < 1e-9])
        ]
    return [
        (f"μ = {mu:g}", dict(restitution=restitution, friction=mu))
        for mu in np.unique(runs["friction"][np.abs(runs["restitution"] - restitution) < 1e-6])
    ]


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--vary", choices=("restitution", "friction"), default="restitution")
    ap.add_argument("--restitution", type=float, default=0.0)
    ap.add_argument("--inset-from", type=float, default=0.74, help="ν where the inset starts")
    ap.add_argument("table")
    ap.add_argument("output")
    args = ap.parse_args()
    table = ct.read_table(args.table)
    res = ct.analyse(table)
    sigma = ct.mean_diameter(table)
    nu_all = table["runs"]["packing_fraction"]
    fig, ax = plt.subplots(figsize=(9, 5))
    inset = ax.inset_axes([0.1, 0.45, 0.42, 0.45]) if args.vary == "restitution" else None
    plotted = 0
    for k, (label, crit) in enumerate(series(table, args.vary, args.restitution)):
        rows = ct.select(table, **crit)
        if len(rows) == 0:
            continue
        nu, xi, err = nu_all[rows], res["xi"][rows] / sigma, res["xi_error"][rows] / sigma
        ok = res["measurable"][rows]
        for a, size in ((ax, 4), (inset, 3)):
            if a is None:
                continue
            show = ok & (nu >= args.inset_from - 1e-9) if a is inset else ok
            a.errorbar(
                nu[show],
                xi[show],
                yerr=err[show],
                fmt="o-",
                ms=size,
                capsize=2,
                color=f"C{k}",
                label=label if a is ax else None,
            )
            beyond = ~ok & (nu >= args.inset_from - 1e-9) if a is inset else ~ok
            a.plot(nu[beyond], xi[beyond], "o", mfc="none", ms=size + 1, color=f"C{k}")
        plotted += 1
    if not plotted:
        sys.exit(f"ch5_xi.py: no runs to plot in {args.table}")
    for a in [ax] + ([inset] if inset is not None else []):
        a.axhline(res["xi_el"] / sigma, color="k", ls="--", lw=0.8)
        a.axhline(res["threshold"] * res["xi_el"] / sigma, color="k", ls=":", lw=0.8)
    if inset is not None:
        inset.set_title(f"ν ≥ {args.inset_from:g}", fontsize=8)
        inset.tick_params(labelsize=7)
    ax.plot(
        [],
        [],
        "o",
        mfc="none",
        color="grey",
        label=f"not measurable: > {100 * res['max_tail_share']:g} % of ∫ℓ|C| beyond 2ℓ_max/3",
    )
    ax.set_xlabel("packing fraction ν")
    ax.set_ylabel(r"$\xi_{|C|}/\sigma$")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    runs = table["runs"]
    what = (
        "Fig. 5.3: ξ for every e, μ = 0"
        if args.vary == "restitution"
        else f"Fig. 5.4: ξ for every μ, e = {args.restitution:g}"
    )
    ax.set_title(
        f"Thesis {what}\nN = {int(runs['grains'][0])}; dashed ξ_el = {res['xi_el'] / sigma:.3f}σ "
        f"(thesis 0.785σ, other normalisation), dotted 1.25 ξ_el",
        fontsize=9,
    )
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
