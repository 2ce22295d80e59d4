#!/usr/bin/env python3
"""pressure_vs_packing.py [TABLE.h5 [OUTPUT.png]]: the steady pressure over the squared shear
rate, p/γ̇², against the packing fraction ν, one curve per restitution e of the frictionless
runs (μ = 0), with the table's blocking errors; an example of the package granflow
(docs/python.md).

TABLE.h5 is the chapter-4 sweep's steady-state table of the quick reproduction,
runs/quick/ch4_sweep.h5 by default (pipelines/analysis/steady_state.py writes it: ν, e, μ and
γ̇ per run under /runs, the steady means and their errors under /steady); OUTPUT.png is
p_over_rate2.png by default. Each point is also printed, with the units the table gives."""
import argparse

import matplotlib

matplotlib.use("Agg")  # a file, no display
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
import numpy as np  # noqa: E402

import granflow  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("table", nargs="?", default="runs/quick/ch4_sweep.h5")
    parser.add_argument("output", nargs="?", default="p_over_rate2.png")
    args = parser.parse_args()

    table = granflow.read_table(args.table)
    runs, steady = table["runs"], table["steady"]
    nu, e = runs["packing_fraction"].values, runs["restitution"].values
    mu, rate = runs["friction"].values, runs["rate"].values
    p, p_error = steady["pressure"], steady["pressure_error"]
    print(f"{table.kind} table {args.table}: {len(nu)} runs")
    print(f"p: {p.meaning} [{p.unit}]; γ̇ in [{runs['rate'].unit}], so p/γ̇² is in [M], the code mass")

    fig, ax = plt.subplots(figsize=(5.5, 4))
    for restitution in sorted(set(e[mu == 0])):
        rows = np.flatnonzero((mu == 0) & (e == restitution))
        rows = rows[np.argsort(nu[rows], kind="stable")]
        y, dy = p.values[rows] / rate[rows] ** 2, p_error.values[rows] / rate[rows] ** 2
        ax.errorbar(nu[rows], y, yerr=dy, fmt="o-", capsize=2, label=f"e = {restitution:g}")
        for row, value, error in zip(rows, y, dy):
            print(f"e = {restitution:g}  ν = {nu[row]:.4f}  p/γ̇² = {value:.6g} ± {error:.2g}")
    ax.set_yscale("log")
    ax.set_xlabel("packing fraction ν")
    ax.set_ylabel(r"$p/\dot\gamma^2$ (M, the code mass)")
    ax.set_title(f"steady pressure, μ = 0 ({table.kind})", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
