#!/usr/bin/env python3
"""ch4_incline_profiles.py [--base-skip D] [--surface-skip D] RUN.h5 OUTPUT.png: thesis Fig. 4.8,
steady depth profiles of one gf-incline run against the height y above the base in mean
diameters: packing fraction ν, V_x/√(g⟨R⟩) (with the fitted Bagnold form V_s − c(H − y)^a of
incline_bulk.py), T/(g⟨R⟩), and the stresses p⟨R⟩/(mg) and s⟨R⟩/(mg) beside the momentum
balance g cos θ W and g sin θ W (eq. 4.8–4.9, W the mass above per unit length).

Normalisation: the thesis' text normalises the stresses "by mg⟨R⟩⁻¹"; its caption writes
p⟨R⟩²/mg, which is not dimensionless for a 2D stress (force per length): we follow the text.
The bulk layers (incline_bulk.py) are shaded."""
import math

import numpy as np

from analysis import incline_bulk as ib
from granflow.plotting import plt, save_figure


def main():
    args, run, row = ib.plot_input(__doc__, "ch4_incline_profiles.py")
    prm, prof = run["parameters"], run["profiles"]
    r, m, g = prm["mean_radius"], prm["mean_mass"], prm["gravity"]
    d = 2 * r
    theta = math.radians(prm["angle"])
    y = prof["y"] / d
    height = row["surface_height"] / d
    stress = r / (m * g)
    panels = [
        ("packing fraction ν", prof["packing_fraction"]),
        (r"$V_x/\sqrt{g\langle R\rangle}$", prof["velocity_x"] / math.sqrt(g * r)),
        (r"$T/g\langle R\rangle$", prof["temperature"] / (g * r)),
        (r"$p\langle R\rangle/mg$", prof["pressure"] * stress),
        (r"$s\langle R\rangle/mg$", prof["shear_stress"] * stress),
    ]
    fig, axes = plt.subplots(1, 5, figsize=(14, 4.2), sharey=True)
    for ax, (label, value) in zip(axes, panels):
        ax.plot(value, y, "o-", ms=4)
        ax.set_xlabel(label)
        ax.axhspan(
            row["bulk_from"] / d - 0.5 * run["bin"] / d,
            row["bulk_to"] / d + 0.5 * run["bin"] / d,
            color="0.9",
            zorder=0,
        )
        ax.axhline(height, color="0.5", ls=":", lw=0.8)
    if row["flowing"]:
        yy = np.linspace(args.base_skip, height, 100)
        a, vs = row["velocity_exponent_full"], row["surface_velocity"]
        fit = np.flatnonzero(np.isfinite(prof["velocity_x"]) & (y >= args.base_skip) & (y < height))
        vfit = prof["velocity_x"][fit] / math.sqrt(g * r)
        c = np.linalg.lstsq((height * d - prof["y"][fit])[:, None] ** a, vs - vfit, rcond=None)[0][0]
        axes[1].plot(
            vs - c * ((height - yy) * d) ** a,
            yy,
            "k--",
            lw=0.8,
            label=f"$V_s - c(H-y)^{{{a:.2f}}}$\n(bulk only: a = {row['velocity_exponent']:.2f})",
        )
        axes[1].legend(fontsize=7, loc="upper left")
    w = prof["weight_above"] * stress
    axes[3].plot(math.cos(theta) * w, y, "k--", lw=0.8, label=r"$\Sigma_{yy}$ balance $g\cos\theta\,W$")
    axes[4].plot(math.sin(theta) * w, y, "k--", lw=0.8, label=r"$g\sin\theta\,W$ (eq. 4.9)")
    axes[3].legend(fontsize=7)
    axes[4].legend(fontsize=7)
    axes[0].set_ylabel("height y above the base (mean diameters)")
    fig.suptitle(
        f"Thesis Fig. 4.8: steady profiles, θ = {prm['angle']:g}°, μ = {prm['friction']:g}, "
        f"e = {prm['restitution']:g}, {prm['grains']} grains, averaged from "
        f"{prm['steady_from_tau']:.0f} τ to {prm['time']:.0f} τ (shaded: bulk; dotted: surface H)",
        fontsize=10,
    )
    fig.tight_layout()
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
