#!/usr/bin/env python3
"""ch4_pressure_parts.py TABLE.h5 OUTPUT.png: thesis Fig. 4.5, the static pressure p^s
(circles, contact term of eq. 4.6) and kinetic pressure p^k (diamonds, streaming term)
against packing fraction for e = 0 and μ = 0, both divided by γ̇²m, from the sweep table
of steady_state.py (error bars: its blocking errors)."""
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
        sys.exit(f"ch4_pressure_parts.py: {args.table} has no run with e = 0 and μ = 0")
    nu, st = table["runs"]["packing_fraction"][rows], table["steady"]
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for name, fmt, label in (
        ("pressure_static_scaled", "o-", r"static $p^s$"),
        ("pressure_kinetic_scaled", "d-", r"kinetic $p^k$"),
    ):
        ax.errorbar(nu, st[name][rows], yerr=st[name + "_error"][rows], fmt=fmt, capsize=2, mfc="none", label=label)
    ax.set_yscale("log")
    ax.set_xlabel("packing fraction ν")
    ax.set_ylabel(r"pressure $/\,\dot\gamma^2 m$")
    ax.legend()
    ax.set_title(
        f"Thesis Fig. 4.5: static and kinetic pressure, e = 0, μ = 0 " f"(N={table['runs']['grains'][rows[0]]})",
        fontsize=10,
    )
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
