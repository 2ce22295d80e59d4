#!/usr/bin/env python3
"""ch4_rheology.py TABLE.h5 OUTPUT.png: thesis Fig. 4.4, steady p/(γ̇²m) and s/(γ̇²m) (left)
and T/(γ̇²<R>²) and s/p (right) against packing fraction, for e = 0 and μ = 0, from the
sweep table of steady_state.py (error bars: its blocking errors)."""
import argparse
import sys

from analysis import steady_state as ss
from granflow.plotting import plt, save_figure


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("table")
    ap.add_argument("output")
    args = ap.parse_args()
    table = ss.read_table(args.table)
    rows = ss.select(table, restitution=0.0, friction=0.0)
    if len(rows) == 0:
        sys.exit(f"ch4_rheology.py: {args.table} has no run with e = 0 and μ = 0")
    nu, st = table["runs"]["packing_fraction"][rows], table["steady"]

    def bars(ax, name, **style):
        return ax.errorbar(nu, st[name][rows], yerr=st[name + "_error"][rows], capsize=2, **style)

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    bars(left, "pressure_scaled", fmt="o-", label=r"$p\,\dot\gamma^{-2}/m$")
    bars(left, "shear_stress_scaled", fmt="s-", label=r"$s\,\dot\gamma^{-2}/m$")
    left.set_yscale("log")
    left.set_ylabel(r"stress $/\,\dot\gamma^2 m$")
    left.legend()
    bars(right, "temperature_scaled", fmt="o-", color="tab:green", label=r"$T\,\dot\gamma^{-2}/\langle R\rangle^2$")
    right.set_yscale("log")
    right.set_ylabel(r"$T\,\dot\gamma^{-2}/\langle R\rangle^2$", color="tab:green")
    twin = right.twinx()
    bars(twin, "s_over_p", fmt="d--", color="tab:red", label="$s/p$")
    twin.set_ylabel("$s/p$", color="tab:red")
    for ax in (left, right):
        ax.set_xlabel("packing fraction ν")
    runs = table["runs"]
    prm = table["parameters"]
    # With --detect-transient each run is averaged from its own steady start, at least from_strain.
    averaged = (
        f"each run from its steady start >= {prm['from_strain']:g}"
        if prm.get("detect_transient")
        else f"strain >= {prm['from_strain']:g} averaged"
    )
    fig.suptitle(
        f"Thesis Fig. 4.4: steady state, e = 0, μ = 0 (N={runs['grains'][rows[0]]}, "
        f"γ̇={runs['rate'][rows[0]]:g}, {averaged})",
        fontsize=10,
    )
    fig.tight_layout()
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
