#!/usr/bin/env python3
"""ch5_phase.py --figure 5.9|5.10 TABLE.h5 OUTPUT.png: the binary-collision crossover ν_bc(e),
where ξ_|C|/ξ_el first crosses 1.25 upward in ν over the measurable runs, as gf-correlate
computes it (/sweep/nu_bc_abs: linear interpolation, errors from the jackknife errors of ξ_|C|
and ξ_el).
Fig. 5.9: ν_bc against e (μ = 0 filled; other μ hollow), with ν_c ≈ 0.845 (thesis).
Fig. 5.10: the phase diagram in (ν, e): every run of the sweep at μ = 0 marked dilute (ξ/ξ_el
< 1.25), dense, or with correlations reaching the box (not measurable, left out of ν_bc), the
ν_bc(e) line and ν_c. Series whose crossing is not bracketed are drawn as
arrows at the end of the ν range they lie beyond."""
import argparse

import numpy as np

from granflow import correlation_table as ct
from granflow.plotting import plt, save_figure


NU_C = 0.845  # thesis' estimate of the jamming packing fraction


def bounds(table, s):
    rows = ct.select(table, restitution=s["restitution"], friction=s["friction"])
    nu = table["runs"]["packing_fraction"][rows]
    return nu.min(), nu.max()


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--figure", choices=("5.9", "5.10"), required=True)
    ap.add_argument("table")
    ap.add_argument("output")
    args = ap.parse_args()
    table = ct.read_table(args.table)
    res = ct.analyse(table)
    runs = table["runs"]
    fig, ax = plt.subplots(figsize=(6.8, 5))
    frictions = sorted({s["friction"] for s in res["series"]})
    note = []
    for s in res["series"]:
        lo, hi = bounds(table, s)
        k = frictions.index(s["friction"])
        style = dict(color=f"C{k}", mfc=f"C{k}" if s["friction"] == 0 else "none")
        e = s["restitution"]
        if s["status"] == "bracketed":
            point = (e, s["nu_bc"]) if args.figure == "5.9" else (s["nu_bc"], e)
            err = dict(yerr=s["nu_bc_error"]) if args.figure == "5.9" else dict(xerr=s["nu_bc_error"])
            ax.errorbar(*point, fmt="o", ms=6, capsize=3, **err, **style)
        elif s["status"] in ("all_below", "all_above"):
            nu = hi if s["status"] == "all_below" else lo
            marker = {
                "5.9": "^" if s["status"] == "all_below" else "v",
                "5.10": ">" if s["status"] == "all_below" else "<",
            }[args.figure]
            ax.plot(*((e, nu) if args.figure == "5.9" else (nu, e)), marker, ms=8, **style)
            note.append(f"e={e:g}, μ={s['friction']:g}: ν_bc {'>' if s['status'] == 'all_below' else '<'} {nu:.3f}")
        else:
            note.append(f"e={e:g}, μ={s['friction']:g}: {s['status']}")
    for k, mu in enumerate(frictions):
        ax.plot([], [], "o", color=f"C{k}", mfc=f"C{k}" if mu == 0 else "none", label=f"ν_bc, μ = {mu:g}")
    frictionless = [s for s in res["series"] if s["friction"] == 0 and s["status"] == "bracketed"]
    if args.figure == "5.9":
        if frictionless:
            ax.plot(
                [s["restitution"] for s in frictionless], [s["nu_bc"] for s in frictionless], "-", color="C0", lw=0.8
            )
        ax.axhline(NU_C, color="k", ls="--", lw=1, label="ν_c ≈ 0.845 (thesis)")
        ax.set_xlabel("restitution e")
        ax.set_ylabel(r"$\nu_{bc}$")
        ax.set_xlim(-0.05, 1.0)
        title = "Thesis Fig. 5.9: ν_bc(e), where ξ_|C|/ξ_el = 1.25"
    else:
        mask = np.abs(runs["friction"]) < 1e-9
        beyond = mask & ~res["measurable"]
        dense = mask & res["measurable"] & (res["ratio"] >= res["threshold"])
        dilute = mask & res["measurable"] & (res["ratio"] < res["threshold"])
        ax.plot(
            runs["packing_fraction"][dilute],
            runs["restitution"][dilute],
            "s",
            ms=4,
            color="tab:green",
            alpha=0.6,
            label="run: ξ/ξ_el < 1.25",
        )
        ax.plot(
            runs["packing_fraction"][dense],
            runs["restitution"][dense],
            "D",
            ms=4,
            color="tab:orange",
            alpha=0.6,
            label="run: ξ/ξ_el ≥ 1.25",
        )
        ax.plot(
            runs["packing_fraction"][beyond],
            runs["restitution"][beyond],
            "x",
            ms=5,
            color="tab:red",
            label="run: correlations reach the box",
        )
        if frictionless:
            ax.plot([s["nu_bc"] for s in frictionless], [s["restitution"] for s in frictionless], "-", color="C0", lw=1)
        ax.axvline(NU_C, color="k", ls="--", lw=1, label="ν_c ≈ 0.845 (thesis)")
        low, high = np.nanmin(runs["packing_fraction"]), NU_C
        ax.text(low + 0.02, 1.03, "dilute inertial\n(binary collisions)", fontsize=8, va="bottom")
        ax.text(0.72, 1.03, "dense inertial\n(force networks)", fontsize=8, va="bottom")
        ax.text(high + 0.004, 0.5, "quasi-\nstatic", fontsize=8, rotation=90, va="center")
        ax.set_xlim(low - 0.02, 0.87)
        ax.set_ylim(-0.05, 1.15)
        ax.set_xlabel("packing fraction ν")
        ax.set_ylabel("restitution e")
        title = "Thesis Fig. 5.10: phase diagram of granular shear flow"
    ax.legend(fontsize=7, loc="lower right" if args.figure == "5.9" else "lower left")
    sigma = ct.mean_diameter(table)
    ax.set_title(
        f"{title}\nN = {int(runs['grains'][0])}, ξ_el = ({res['xi_el'] / sigma:.3f} ± "
        f"{res['xi_el_error'] / sigma:.3f})σ" + ("\n" + "; ".join(note) if note else ""),
        fontsize=8,
    )
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
