#!/usr/bin/env python3
"""ch4_invariants.py RUN.h5 OUTPUT.png [--from-strain S]: thesis Fig. 4.3, the three
invariant dimensionless groups s/p, γ̇<R>/√T and mT/(p<R>²) of one run against shear
strain, with their steady means ± blocking error (steady_state.py) over strain >= S."""
import argparse

from analysis import steady_state as ss
from granflow.plotting import plt, save_figure


PANELS = (
    ("s_over_p", r"$s/p$"),
    ("rate_R_over_sqrt_T", r"$\dot\gamma\langle R\rangle/\sqrt{T}$"),
    ("mT_over_pR2", r"$mT/p\langle R\rangle^2$"),
)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("input")
    ap.add_argument("output")
    ss.add_start_options(ap)
    args = ap.parse_args()
    run = ss.read_run(args.input)
    series = ss.invariant_series(run)
    start = ss.steady_start(run, args.from_strain, args.detect_transient)
    steady = ss.steady_values(run, start)[0]
    fig, axes = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    for ax, (name, label) in zip(axes, PANELS):
        ax.plot(run["series"]["strain"], series[name], lw=0.5, color="tab:blue")
        value, err, _ = steady[name]
        ax.axhspan(value - err, value + err, color="tab:orange", alpha=0.4)
        ax.axhline(value, color="tab:orange", lw=1, label=f"steady {value:.4g} ± {err:.2g}")
        ax.axvline(start, color="0.5", ls="--", lw=0.8)
        ax.set_ylabel(label)
        ax.legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel(r"shear strain $\dot\gamma t$")
    prm = run["parameters"]
    fig.suptitle(
        f"Thesis Fig. 4.3: invariants, ν={prm['packing_fraction']:.3f}, e={prm['restitution']:g}, "
        f"μ={prm['friction']:g}, γ̇={prm['rate']:g}, N={prm['grains']}",
        fontsize=10,
    )
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
