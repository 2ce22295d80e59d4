#!/usr/bin/env python3
"""ch5_anisotropy.py --figure 5.5|5.6 TABLE.h5 OUTPUT.png: the angular dependence of ξ from
gf-correlate's sweep table (its ξ(θ) of eq. 5.2 per sector, jackknife errors, and its fit of
eq. 5.3). Only runs whose eq.-5.2 ξ is well defined are shown (ξ > 0 with relative error below
--max-relative-error, correlations not reaching the box): in dense flows the signed integrals behind ξ(θ) change sign (see
correlation_table.py) and ξ(θ)/ξ means nothing there.
Fig. 5.5: ξ(θ)/σ for e = E, μ = 0 at the three highest such ν, with each run's fit.
Fig. 5.6: 2πξ(θ)/ξ of every such run at μ = 0 (colour: e), the fit of eq. 5.3 to all of them
(linear weighted least squares, correlation_table.fit_anisotropy) and the thesis' curve
(a0 = 0.21, θ0 = 0.013)."""
import argparse

import numpy as np

from granflow import correlation_table as ct
from granflow.plotting import plt, save_figure


THESIS_A0, THESIS_THETA0 = 0.21, 0.013


def well_defined(table, rows, max_relative_error):
    """Rows whose eq.-5.2 ξ is positive with a small relative error and whose correlations do
    not reach the box (gf-correlate's /correlation/measurable)."""
    cor = table["correlation"]
    xi, err = cor["xi"][rows], cor["xi_error"][rows]
    measurable = ct.analyse(table)["measurable"][rows]
    return rows[(xi > 0) & np.isfinite(err) & (err < max_relative_error * xi) & measurable]


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--figure", choices=("5.5", "5.6"), required=True)
    ap.add_argument("--restitution", type=float, default=0.0, help="e of Fig. 5.5")
    ap.add_argument("--max-relative-error", type=float, default=0.2)
    ap.add_argument("table")
    ap.add_argument("output")
    args = ap.parse_args()
    table = ct.read_table(args.table)
    cor, runs = table["correlation"], table["runs"]
    sigma = ct.mean_diameter(table)
    theta = cor["theta"]
    width = float(np.pi / len(theta))
    grid = np.linspace(0, np.pi, 200)
    fig, ax = plt.subplots(figsize=(6.8, 4.8))
    runs_note = ""
    if args.figure == "5.5":
        rows = well_defined(
            table, ct.select(table, restitution=args.restitution, friction=0.0), args.max_relative_error
        )[-3:]
        for k, row in enumerate(rows):
            xi = cor["xi"][row]
            ax.errorbar(
                theta,
                cor["xi_theta"][row] / sigma,
                yerr=cor["xi_theta_error"][row] / sigma,
                fmt="o",
                ms=3,
                capsize=2,
                color=f"C{k}",
                label=f"ν = {runs['packing_fraction'][row]:.3f}: a0 = {cor['a0'][row]:.2f} ± "
                f"{cor['a0_error'][row]:.2f}, θ0 = {cor['theta0'][row]:.2f} ± "
                f"{cor['theta0_error'][row]:.2f}",
            )
            ax.plot(
                grid,
                xi / (2 * np.pi) * ct.eq53(grid, cor["a0"][row], cor["theta0"][row]) / sigma,
                "-",
                color=f"C{k}",
                lw=1,
            )
        ax.set_ylabel(r"$\xi(\theta)/\sigma$")
        title = f"Thesis Fig. 5.5: ξ(θ), e = {args.restitution:g}, μ = 0, with the fits of eq. 5.3"
    else:
        rows = well_defined(table, ct.select(table, friction=0.0), args.max_relative_error)
        es = np.unique(runs["restitution"][rows])
        ys, errs, thetas = [], [], []
        for row in rows:
            xi = cor["xi"][row]
            y, err = 2 * np.pi * cor["xi_theta"][row] / xi, 2 * np.pi * cor["xi_theta_error"][row] / xi
            k = int(np.searchsorted(es, runs["restitution"][row]))
            ax.plot(theta, y, "o", ms=2.5, alpha=0.6, color=plt.get_cmap("viridis")(k / max(len(es) - 1, 1)))
            ys.append(y)
            errs.append(err)
            thetas.append(theta)
        for k, e in enumerate(es):
            ax.plot([], [], "o", color=plt.get_cmap("viridis")(k / max(len(es) - 1, 1)), label=f"e = {e:g}")
        if rows.size:
            fit = ct.fit_anisotropy(np.concatenate(thetas), np.concatenate(ys), np.concatenate(errs), width)
            ax.plot(
                grid,
                ct.eq53(grid, fit["a0"], fit["theta0"]),
                "k-",
                lw=1.5,
                label=f"fit: a0 = {fit['a0']:.3f} ± {fit['a0_error']:.3f}, θ0 = {fit['theta0']:.3f} ± "
                f"{fit['theta0_error']:.3f}",
            )
        ax.plot(
            grid,
            ct.eq53(grid, THESIS_A0, THESIS_THETA0),
            "k--",
            lw=1,
            label=f"thesis: a0 = {THESIS_A0}, θ0 = {THESIS_THETA0}",
        )
        ax.set_ylabel(r"$2\pi\,\xi(\theta)/\xi$")
        title = "Thesis Fig. 5.6: normalised ξ(θ), μ = 0, all runs with a well-defined ξ"
        runs_note = f", {len(rows)} runs"
    ax.axvline(3 * np.pi / 4, color="grey", lw=0.6, ls=":")
    ax.set_xlim(0, np.pi)
    ax.set_xticks([0, np.pi / 4, np.pi / 2, 3 * np.pi / 4, np.pi])
    ax.set_xticklabels(["0", "π/4", "π/2", "3π/4 (compression)", "π"])
    ax.set_xlabel("θ (angle of ℓ to the flow direction x)")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)
    else:
        ax.text(0.5, 0.5, "no run with a well-defined ξ", transform=ax.transAxes, ha="center")
    ax.set_title(
        f"{title}\n(gf-correlate's eq.-5.2 ξ(θ); N = {int(runs['grains'][0])}{runs_note}; "
        f"runs with δξ/ξ < {args.max_relative_error:g})",
        fontsize=9,
    )
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
