#!/usr/bin/env python3
"""convergence_step.py CONVERGENCE.h5 OUTPUT.png: the companion of thesis Fig. 4.2 that tests the
time step. Fig. 4.2 scales the rate at a fixed strain step γ̇dt, which leaves every dimensionless
number unchanged by construction; here p/(mγ̇²), s/p and T/(γ̇²⟨R⟩²) are drawn against γ̇dt at
fixed γ̇, one line per state point of the convergence study (the series of convergence.py with
the most steps per point, default tolerance), with their errors; the default step is marked."""
import argparse

import h5py
import numpy as np

from granflow.hdf5 import read_attrs, read_group
from granflow.plotting import plt, save_figure

PANELS = (("p", r"$p/(m\dot\gamma^2)$", True), ("s_over_p", r"$s/p$", False), ("T", r"$T/(\dot\gamma^2\langle R\rangle^2)$", True))


def series(table, tolerance):
    """{(N, ν, e, μ): {observable: (steps, values, errors)}} at the given tolerance, the N with
    the most steps per point."""
    s = table["series"]
    keep = np.isclose(s["tolerance"], tolerance, rtol=1e-9, atol=0)
    points = {}
    for k in np.flatnonzero(keep):
        key = (int(s["grains"][k]), s["packing_fraction"][k], s["restitution"][k], s["friction"][k])
        entry = points.setdefault(key, {}).setdefault(s["observable"][k], ([], [], []))
        for column, name in zip(entry, ("step", "value", "error")):
            column.append(s[name][k])
    best = {}
    for key, obs in points.items():
        steps = len(obs.get("p", ([],))[0])
        point = key[1:]
        if point not in best or steps > best[point][0]:
            best[point] = (steps, key, obs)
    return {b[1]: b[2] for b in best.values()}


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("table")
    ap.add_argument("output")
    args = ap.parse_args()
    with h5py.File(args.table, "r") as f:
        table = {"series": read_group(f["series"]), "parameters": read_attrs(f["parameters"])}
    params = table["parameters"]
    data = series(table, float(params["tolerance"]))
    fig, axes = plt.subplots(1, len(PANELS), figsize=(13, 4))
    for ax, (name, label, log) in zip(axes, PANELS):
        for (grains, nu, e, mu), obs in sorted(data.items()):
            if name not in obs:
                continue
            h, q, err = (np.asarray(v, dtype=float) for v in obs[name])
            order = np.argsort(h)
            ax.errorbar(h[order], q[order], yerr=np.nan_to_num(err[order]), marker="o", ms=3, capsize=2,
                        label=f"ν={nu:.2f}, e={e:g}, μ={mu:g}, N={grains}")
        ax.axvline(float(params["default_step"]), color="0.5", ls="--", lw=0.8)
        ax.set_xscale("log")
        if log:
            ax.set_yscale("log")
        ax.set_xlabel(r"strain step $\dot\gamma\,dt$")
        ax.set_ylabel(label)
    axes[0].legend(fontsize=7)
    fig.suptitle("Fig. 4.2's companion: the steady stresses against the step at fixed γ̇ (dashed: the default step)",
                 fontsize=10)
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
