#!/usr/bin/env python3
"""ch4_bagnold.py OUTPUT.png RUN.h5... [--from-strain S]: thesis Fig. 4.2, the raw normalised
pressure p/(γ̇²m) against shear strain for the same packing sheared at different rates
(one panel per rate, slowest on top); Bagnold scaling makes the traces identical. The band
is the steady mean ± its blocking error (steady_state.py) over strain >= S."""
import argparse

from analysis import steady_state as ss
from granflow.plotting import plt, save_figure


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("output")
    ap.add_argument("runs", nargs="+")
    ss.add_start_options(ap)
    args = ap.parse_args()
    runs = sorted((ss.read_run(p) for p in args.runs), key=lambda r: r["parameters"]["rate"])
    fig, axes = plt.subplots(len(runs), 1, figsize=(7, 2.4 * len(runs)), sharex=True, sharey=True, squeeze=False)
    for ax, run in zip(axes[:, 0], runs):
        prm, ser = run["parameters"], run["series"]
        scale = 1 / (prm["rate"] ** 2 * prm["mean_mass"])
        ax.plot(ser["strain"], ser["pressure"] * scale, lw=0.5, color="tab:blue")
        start = ss.steady_start(run, args.from_strain, args.detect_transient)
        value, err, _ = ss.steady_values(run, start)[0]["pressure_scaled"]
        ax.axhspan(value - err, value + err, color="tab:orange", alpha=0.4)
        ax.axhline(value, color="tab:orange", lw=1, label=f"steady mean {value:.4g} ± {err:.2g}")
        ax.axvline(start, color="0.5", ls="--", lw=0.8)
        ax.set_yscale("log")
        ax.set_ylabel(r"$p\,\dot\gamma^{-2}/m$")
        ax.legend(loc="upper right", fontsize=8, title=f"γ̇ = {prm['rate']:g}, dt = {prm['dt']:.3g}", title_fontsize=8)
    axes[-1, 0].set_xlabel(r"shear strain $\dot\gamma t$")
    prm = runs[0]["parameters"]
    fig.suptitle(
        f"Thesis Fig. 4.2: Bagnold scaling, ν={prm['packing_fraction']:.3f}, e={prm['restitution']:g}, "
        f"μ={prm['friction']:g}, N={prm['grains']}",
        fontsize=10,
    )
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
