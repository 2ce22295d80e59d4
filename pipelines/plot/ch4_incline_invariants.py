#!/usr/bin/env python3
"""ch4_incline_invariants.py [--base-skip D] [--surface-skip D] RUN.h5 OUTPUT.png: thesis
Fig. 4.9, the three Bagnold invariants s/p, γ̇⟨R⟩/√T and mT/(p⟨R⟩²) of one gf-incline run
against the height above the base in mean diameters, with their bulk means (incline_bulk.py,
shaded layers) and, for s/p, tan θ (what the momentum balance imposes when Σxx = Σyy)."""
import math

from analysis import incline_bulk as ib
from granflow.plotting import plt, save_figure


def main():
    args, run, row = ib.plot_input(__doc__, "ch4_incline_invariants.py")
    prm, prof = run["parameters"], run["profiles"]
    d = 2 * prm["mean_radius"]
    y = prof["y"] / d
    fig, axes = plt.subplots(3, 1, figsize=(6, 8), sharex=True)
    for ax, name, label in zip(
        axes,
        ("s_over_p", "inertial", "mT_over_pR2"),
        ("$s/p$", r"$\dot\gamma\langle R\rangle/\sqrt{T}$", r"$mT/p\langle R\rangle^2$"),
    ):
        ax.plot(y, prof[name], "o-", ms=4)
        ax.axvspan(
            row["bulk_from"] / d - 0.5 * run["bin"] / d,
            row["bulk_to"] / d + 0.5 * run["bin"] / d,
            color="0.9",
            zorder=0,
        )
        if row["flowing"]:
            ax.axhline(
                row[name], color="k", ls="--", lw=0.8, label=f"bulk {row[name]:.4g} ± {row[name + '_error']:.2g}"
            )
        if name == "s_over_p":
            ax.axhline(math.tan(math.radians(prm["angle"])), color="tab:red", ls=":", lw=1, label=r"$\tan\theta$")
        ax.set_ylabel(label)
        ax.legend(fontsize=8)
        finite = prof[name][(y > 0.5) & (y < row["surface_height"] / d)]
        if len(finite):
            lo, hi = min(finite.min(), row[name] if row["flowing"] else finite.min()), finite.max()
            ax.set_ylim(lo - 0.2 * (hi - lo + 1e-3), hi + 0.2 * (hi - lo + 1e-3))
    axes[-1].set_xlabel("height y above the base (mean diameters)")
    fig.suptitle(
        f"Thesis Fig. 4.9: Bagnold invariants, θ = {prm['angle']:g}°, μ = {prm['friction']:g}, "
        f"e = {prm['restitution']:g}\n(shaded: bulk layers; layers above the surface H = "
        f"{row['surface_height'] / d:.1f} diameters off scale)",
        fontsize=10,
    )
    fig.tight_layout()
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
