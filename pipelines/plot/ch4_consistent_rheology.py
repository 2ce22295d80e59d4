#!/usr/bin/env python3
"""ch4_consistent_rheology.py [--restitution E] [--min-nu NU] INCLINE_TABLE.h5 SHEAR_TABLE.h5
OUTPUT.png: thesis Fig. 4.10, s/p (top), γ̇⟨R⟩/√T (middle) and mT/(p⟨R⟩²) (bottom) against
packing fraction, from the bulk of incline flow (squares: incline_bulk.py table, one point per
flowing run, error bars the scatter of the bulk layers) and from simple shear (circles:
steady_state.py table, blocking errors), for μ = 0 (left) and μ = 0.4 (right). Shear runs at
restitution E (the incline's) with ν ≥ NU (0.7): like the thesis, only the dense shear data.
mT/(p⟨R⟩²) on a log scale (it spans decades near ν_max)."""
import argparse

import numpy as np

from analysis import incline_bulk as ib
from analysis import steady_state as ss
from granflow.plotting import plt, save_figure


INVARIANTS = (
    ("s_over_p", "s_over_p", "$s/p$"),
    ("inertial", "rate_R_over_sqrt_T", r"$\dot\gamma\langle R\rangle/\sqrt{T}$"),
    ("mT_over_pR2", "mT_over_pR2", r"$mT/p\langle R\rangle^2$"),
)
FRICTIONS = (0.0, 0.4)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--restitution", type=float, default=0.5)
    ap.add_argument("--min-nu", type=float, default=0.7)
    ap.add_argument("incline")
    ap.add_argument("shear")
    ap.add_argument("output")
    args = ap.parse_args()
    incline, shear = ib.read_table(args.incline), ss.read_table(args.shear)
    fig, axes = plt.subplots(3, 2, figsize=(10, 9), sharex="col")
    for col, mu in enumerate(FRICTIONS):
        rows = ss.select(shear, friction=mu, restitution=args.restitution)
        rows = rows[shear["runs"]["packing_fraction"][rows] >= args.min_nu]
        inc = np.flatnonzero(np.isclose(incline["runs"]["friction"], mu) & (incline["runs"]["flowing"] == 1))
        for row, (name, shear_name, label) in enumerate(INVARIANTS):
            ax = axes[row, col]
            if len(rows):
                ax.errorbar(
                    shear["runs"]["packing_fraction"][rows],
                    shear["steady"][shear_name][rows],
                    yerr=shear["steady"][shear_name + "_error"][rows],
                    fmt="o",
                    mfc="none",
                    capsize=2,
                    label="simple shear",
                )
            if len(inc):
                ax.errorbar(
                    incline["bulk"]["packing_fraction"][inc],
                    incline["bulk"][name][inc],
                    xerr=incline["bulk"]["packing_fraction_error"][inc],
                    yerr=incline["bulk"][name + "_error"][inc],
                    fmt="s",
                    capsize=2,
                    color="tab:red",
                    label="incline bulk",
                )
                for i in inc:
                    ax.annotate(
                        f"{incline['runs']['angle'][i]:g}°",
                        (incline["bulk"]["packing_fraction"][i], incline["bulk"][name][i]),
                        textcoords="offset points",
                        xytext=(4, 4),
                        fontsize=7,
                        color="tab:red",
                    )
            if not len(rows) and not len(inc):
                ax.text(0.5, 0.5, "no data", transform=ax.transAxes, ha="center")
            elif not len(inc) and row == 0:
                ax.text(
                    0.3,
                    0.1,
                    "no flowing incline run at this μ",
                    transform=ax.transAxes,
                    ha="center",
                    fontsize=8,
                    color="tab:red",
                )
            ax.set_ylabel(label)
            if name == "mT_over_pR2":
                ax.set_yscale("log")  # spans decades as ν → ν_max
            if row == 0:
                ax.set_title(f"μ = {mu:g}")
                ax.legend(fontsize=8)
        axes[-1, col].set_xlabel("packing fraction ν")
    fig.suptitle(
        f"Thesis Fig. 4.10: bulk rheology of simple shear (circles, ν ≥ {args.min_nu:g}) and incline "
        f"flow (squares, angle beside each), e = {args.restitution:g}",
        fontsize=10,
    )
    fig.tight_layout()
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
