#!/usr/bin/env python3
"""ch6_kinetic.py KINETIC.h5 CORRELATE.h5 OUTPUT.png --restitutions E1 E2: thesis Figs 6.1-6.3
(one pair of restitutions each: 0.92 and 0.75, 0.5 and 0.25, 0.1 and 0). Left: the static and
collisional pressures p^s/p⁰ and p^bc/p⁰ (eqs 2.8, 6.2) against ν with the Enskog prediction
(1+e)χν (eq. 6.9, a line). Right: s^s/(γ̇η⁰) and s^bc/(γ̇η⁰) with the two shear-stress
predictions, eq. 6.10 as printed (dashed) and the 2D Garzó–Dufty collisional viscosity
(dotted). Every value is gf-kinetic's (KINETIC.h5, /runs); error bars its blocked errors.
Points are filled where gf-correlate's ξ/ξ_el > 1.25 (CORRELATE.h5, matched by run path) or
the correlations reach the box, open otherwise, as the thesis colours them. Inset (left panel):
C_v (eq. 6.11, gf-kinetic's velocity_correlation) against ν with its molecular-chaos baseline
(dashed). The y axes are logarithmic: the normalised static stresses grow by decades towards
jamming, where T falls; non-positive values are left out of a log axis."""
import argparse
import sys

import numpy as np

from granflow import correlation_table as ct
from granflow import kinetic_table as kt
from granflow.plotting import plt, save_figure


def points(ax, nu, y, err, full, color, marker, label):
    """Error bars for every point a log axis can show (finite, positive), filled markers where
    `full`, open ones elsewhere."""
    shown = np.isfinite(y) & (y > 0)
    nu, y, err, full = nu[shown], y[shown], np.where(np.isfinite(err[shown]), err[shown], 0), full[shown]
    ax.errorbar(nu, y, yerr=np.minimum(err, 0.999 * y), fmt="none", ecolor=color, elinewidth=0.8, capsize=2)
    ax.plot(nu[full], y[full], marker, color=color, ms=5, ls="none")
    ax.plot(nu[~full], y[~full], marker, color=color, mfc="none", ms=5, ls="none")
    ax.plot([], [], marker, color=color, mfc="none", ls="none", label=label)


def curve(ax, nu, y, style, color, label):
    """A prediction through the runs' ν, where a log axis can show it."""
    shown = np.isfinite(y) & (y > 0)
    ax.plot(nu[shown], y[shown], style, color=color, lw=1, label=label)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--restitutions", type=float, nargs=2, required=True, metavar="E")
    ap.add_argument("kinetic")
    ap.add_argument("correlate")
    ap.add_argument("output")
    args = ap.parse_args()
    table = kt.read_table(args.kinetic)
    ratio, _, measurable = kt.xi_ratio(table, ct.read_table(args.correlate))
    full_all = kt.filled(ratio, measurable)
    nu_all = kt.column(table, "packing_fraction")
    p0, eta0, rate = (kt.column(table, n) for n in ("p0", "eta0", "rate"))
    baseline = float(table["runs"]["attrs"].get("velocity_correlation_baseline", -0.25))
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 5))
    inset = left.inset_axes([0.12, 0.56, 0.36, 0.38])
    plotted = 0
    for k, e in enumerate(args.restitutions):
        rows = kt.select(table, e)
        if len(rows) == 0:
            continue
        plotted += 1
        c = f"C{k}"
        nu, full = nu_all[rows], full_all[rows]
        with np.errstate(invalid="ignore", divide="ignore"):
            for name, marker, what in (("p_static", "o", "p^s"), ("p_collisional", "s", "p^{bc}")):
                y = kt.column(table, name)[rows] / p0[rows]
                err = kt.column(table, name + "_error")[rows] / p0[rows]
                points(left, nu, y, err, full, c, marker, f"${what}/p^0$, e = {e:g}")
            curve(left, nu, kt.column(table, "p_enskog")[rows] / p0[rows], "-", c, f"$(1+e)\\chi\\nu$, e = {e:g}")
            scale = rate[rows] * eta0[rows]
            for name, marker, what in (("s_static", "o", "s^s"), ("s_collisional", "s", "s^{bc}")):
                y = kt.column(table, name)[rows] / scale
                err = kt.column(table, name + "_error")[rows] / scale
                points(right, nu, y, err, full, c, marker, f"${what}/\\dot\\gamma\\eta^0$, e = {e:g}")
            curve(right, nu, kt.column(table, "s_enskog_thesis")[rows] / scale, "--", c, f"eq. 6.10 as printed, e = {e:g}")
            curve(right, nu, kt.column(table, "s_enskog_2d")[rows] / scale, ":", c, f"2D Garzó–Dufty, e = {e:g}")
        cv, cv_err = kt.column(table, "velocity_correlation")[rows], kt.column(table, "velocity_correlation_error")[rows]
        shown = np.isfinite(cv)
        inset.errorbar(nu[shown], cv[shown], yerr=cv_err[shown], fmt="none", ecolor=c, elinewidth=0.8, capsize=2)
        inset.plot(nu[shown & full], cv[shown & full], "o", color=c, ms=3, ls="none")
        inset.plot(nu[shown & ~full], cv[shown & ~full], "o", color=c, mfc="none", ms=3, ls="none")
    if not plotted:
        sys.exit(f"ch6_kinetic.py: no runs at e = {args.restitutions} in {args.kinetic}")
    inset.axhline(baseline, color="k", ls="--", lw=0.8)
    inset.set_xlabel("ν", fontsize=7)
    inset.set_ylabel("$C_v$", fontsize=7)
    inset.tick_params(labelsize=6)
    inset.set_title(f"$C_v$ (eq. 6.11); dashed: molecular chaos {baseline:g}", fontsize=7)
    for ax, what in ((left, "pressure / $p^0$"), (right, r"shear stress / $\dot\gamma\eta^0$")):
        ax.set_yscale("log", nonpositive="mask")
        ax.set_xlabel("packing fraction ν")
        ax.set_ylabel(what)
        ax.legend(fontsize=7, loc="lower right")
    runs = table["runs"]
    pair = " and ".join(f"{e:g}" for e in args.restitutions)
    fig.suptitle(
        f"Thesis Figs 6.1–6.3: e = {pair}; N = {int(np.max(runs['grains']))}. Filled: ξ/ξ_el > "
        f"{kt.XI_THRESHOLD:g} (gf-correlate), open: below; ○ static, □ collisional",
        fontsize=9,
    )
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
