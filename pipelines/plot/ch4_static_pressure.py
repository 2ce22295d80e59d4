#!/usr/bin/env python3
"""ch4_static_pressure.py TABLE.h5 OUTPUT.png: thesis Fig. 4.6, the static pressure p^s/(γ̇²m)
against packing fraction for every restitution e of the sweep at μ = 0, from the sweep
table of steady_state.py (error bars: its blocking errors)."""
import argparse
import sys

import numpy as np

from analysis import steady_state as ss
from granflow.plotting import plt, save_figure


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("table")
    ap.add_argument("output")
    args = ap.parse_args()
    table = ss.read_table(args.table)
    frictionless = ss.select(table, friction=0.0)
    if len(frictionless) == 0:
        sys.exit(f"ch4_static_pressure.py: {args.table} has no run with μ = 0")
    st = table["steady"]
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for e in np.unique(table["runs"]["restitution"][frictionless]):
        rows = ss.select(table, friction=0.0, restitution=e)
        ax.errorbar(
            table["runs"]["packing_fraction"][rows],
            st["pressure_static_scaled"][rows],
            yerr=st["pressure_static_scaled_error"][rows],
            fmt="o-",
            ms=4,
            capsize=2,
            label=f"e = {e:g}",
        )
    ax.set_yscale("log")
    ax.set_xlabel("packing fraction ν")
    ax.set_ylabel(r"static pressure $p^s/\,\dot\gamma^2 m$")
    ax.legend()
    ax.set_title(
        f"Thesis Fig. 4.6: static pressure for several e, μ = 0 " f"(N={table['runs']['grains'][frictionless[0]]})",
        fontsize=10,
    )
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
