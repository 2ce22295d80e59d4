#!/usr/bin/env python3
"""ch5_correlation.py [--restitution E --nu NU --nus NU1,NU2,...] TABLE.h5 OUTPUT.png: thesis
Fig. 5.2 from gf-correlate's sweep table, μ = 0. Left: the isotropic C̄(ℓ) of the run nearest
to NU (band: jackknife error). Right: log|C̄(ℓ)| for the runs nearest to NU1, NU2, ... (radial
bins merged into gf-correlate's coarse bins of ξ_|C|; hollow markers where C̄ < 0) with the
lines A·exp(−ℓ/ξ_|C|), ξ_|C| gf-correlate's decay length (/correlation/xi_abs) and A fitted to
the points above noise. Without
a run at E, the nearest e of the table is used."""
import argparse
import sys

import numpy as np

from granflow import correlation_table as ct
from granflow.plotting import plt, save_figure


def floats(text):
    return [float(x) for x in text.split(",") if x]


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--restitution", type=float, default=0.25)
    ap.add_argument("--friction", type=float, default=0.0)
    ap.add_argument("--nu", type=float, default=0.81)
    ap.add_argument("--nus", type=floats, default=[0.6, 0.77, 0.81])
    ap.add_argument("table")
    ap.add_argument("output")
    args = ap.parse_args()
    table = ct.read_table(args.table)
    res = ct.analyse(table)
    cor, runs = table["correlation"], table["runs"]
    sigma = ct.mean_diameter(table)
    same_mu = np.abs(runs["friction"] - args.friction) < 1e-6
    if not same_mu.any():
        sys.exit(f"ch5_correlation.py: {args.table} has no run with μ = {args.friction:g}")
    # The e asked for, or the nearest e of the table (small sweeps).
    es = runs["restitution"][same_mu]
    restitution = float(es[np.argmin(np.abs(es - args.restitution))])
    crit = dict(restitution=restitution, friction=args.friction)
    main_row = ct.nearest(table, args.nu, **crit)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    r = cor["r"] / sigma
    c, err = cor["C"][main_row], cor["C_error"][main_row]
    left.fill_between(r, c - err, c + err, color="tab:blue", alpha=0.3, lw=0)
    left.plot(r, c, "-", color="tab:blue", lw=0.8)
    left.axhline(0, color="k", lw=0.5)
    left.set_xlim(0, r[-1])
    left.set_xlabel(r"$\ell/\sigma$")
    left.set_ylabel(r"$\bar C(\ell)$ (per unit area)")
    left.set_title(
        f"ν = {runs['packing_fraction'][main_row]:.3f}, e = {restitution:g}, "
        f"ξ_|C|/ξ_el = {res['ratio'][main_row]:.2f}"
        + ("" if res["measurable"][main_row] else " (correlations reach the box: not measurable)"),
        fontsize=9,
    )
    rows = []
    for nu in args.nus:
        row = ct.nearest(table, nu, **crit)
        if row is not None and row not in rows:
            rows.append(row)
    for k, row in enumerate(rows):
        colour = f"C{k}"
        rb, cb, eb = ct.rebin(cor["r"], cor["C"][row], cor["C_error"][row], res["factor"])
        signal = np.abs(cb) > 2 * eb
        pos, neg = signal & (cb > 0), signal & (cb < 0)
        xi = res["xi"][row]
        label = f"ν = {runs['packing_fraction'][row]:.3f}, ξ_|C| = {xi / sigma:.2f}σ" + (
            "" if res["measurable"][row] else " (reaches the box)"
        )
        right.plot(rb[pos] / sigma, np.abs(cb[pos]), "o", color=colour, ms=4, label=label)
        right.plot(rb[neg] / sigma, np.abs(cb[neg]), "o", mfc="none", color=colour, ms=4)
        right.plot(rb[~signal] / sigma, np.abs(cb[~signal]), ".", color=colour, ms=2, alpha=0.4)
        if np.isfinite(xi) and signal.any():
            log_a = np.mean(np.log(np.abs(cb[signal])) + rb[signal] / xi)
            x = np.linspace(rb[signal].min(), rb[-1], 100)
            right.plot(x / sigma, np.exp(log_a - x / xi), "-", color=colour, lw=1)
    right.set_yscale("log")
    right.set_xlabel(r"$\ell/\sigma$")
    right.set_ylabel(r"$|\bar C(\ell)|$")
    right.legend(fontsize=8, title="filled: C̄ > 0, hollow: C̄ < 0, dots: < 2 s.e.", title_fontsize=7)
    fig.suptitle(
        f"Thesis Fig. 5.2: force correlation, e = {restitution:g}, μ = {args.friction:g} "
        f"(N = {int(runs['grains'][main_row])}, {int(runs['frames'][main_row])} frames; "
        f"lines A·exp(−ℓ/ξ_|C|))",
        fontsize=10,
    )
    fig.tight_layout()
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
