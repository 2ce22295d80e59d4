#!/usr/bin/env python3
"""unconverged_steps.py [--from-strain S] [--csv FILE] RUN.h5 [RUN.h5 ...]: what the steps that
ended at the sweep cap did to p, s/p and T of a gf-shear run observed every step.

A step at `--max-iterations` keeps its last iterate (docs/method/solver.md, "Steps at the cap").
This script measures whether that shows in the observables. Per run, over the rows at strain >= S
(default 1), with `capped` the steps at the cap (/observables/unconverged_steps; in files from
before that column, a final solver_residual at or above the run's tolerance) and `isolated` the
capped steps whose two neighbouring steps converged:
  - capped, isolated: how many; residual_median, residual_max: their final residuals in units of
    the tolerance;
  - per observable x in p, s/p, T:
      percentile: mean over the capped steps of the share of converged steps below them (0.5 when
      the capped steps are typical of the run);
      spike_capped_p10/_p50/_p90: quantiles of x_k/((x_(k-1) + x_(k+1))/2) over the isolated capped
      steps k (1 when x passes smoothly through the step; a policy artefact would be a one-step
      spike);
      spike_nearby_p10/_p50/_p90: the same over the converged steps k within NEAR = 10 steps of a
      capped one whose k-1, k+1 converged too (the same episodes of the flow);
      spike_ordinary_p10/_p50/_p90: the same over all such converged steps of the window;
      drop_effect: relative change of the window's mean of x when the capped steps are left out,
      (mean without - mean with)/mean with;
      spike_effect: what the isolated capped steps' departures from their neighbours add to the
      window's mean, sum over them of (x_k - (x_(k-1) + x_(k+1))/2) / (rows · mean): a bound on
      what an artefact of the last iterate does to the average.
An artefact of the last iterate would show as spikes at the capped steps beyond those of the
converged steps nearby; a difference from the run's mean that the converged neighbours share is
a property of the states where the solver stalls, not of the policy.

Output: a table on stdout, one line per run and observable (with --csv also to FILE, written
atomically, a comment line first). Bad input (no such file, not a gf-shear trajectory, no
tolerance, rows not one per step, too few rows in the window, no capped step or no converged
one): exit 2, one line, nothing written.
"""
import argparse
import shlex
import sys

import h5py
import numpy as np

from granflow import outputs
from granflow.hdf5 import read_attrs, text

OBSERVABLES = ("p", "s/p", "T")
MIN_ROWS = 100
NEAR = 10


class Parser(argparse.ArgumentParser):
    def error(self, message):
        print(f"unconverged_steps.py: error: {message}", file=sys.stderr)
        sys.exit(2)


def read_run(path):
    """(tolerance, steps, strain, residual, capped, {p, s/p, T}) of one gf-shear trajectory."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        raise ValueError(f"{path}: cannot read ({e})") from None
    with f:
        prm = read_attrs(f["parameters"]) if "parameters" in f else {}
        if text(prm.get("program", "")) != "gf-shear" or "observables" not in f:
            raise ValueError(f"{path}: not a gf-shear trajectory")
        obs = f["observables"]
        need = ("strain", "pressure", "shear_stress", "temperature", "solver_residual")
        missing = [n for n in need if n not in obs]
        if missing:
            raise ValueError(f"{path}: /observables lacks {', '.join(missing)}")
        steps = np.asarray(obs["pressure/step"][()], dtype=np.int64)
        series = {n: np.asarray(obs[n + "/value"][()], dtype=float) for n in need}
        if "tolerance" not in prm:
            raise ValueError(f"{path}: /parameters lacks tolerance")
        tolerance = float(prm["tolerance"])
        if "unconverged_steps" in obs:
            capped = np.asarray(obs["unconverged_steps/value"][()]) > 0
        else:
            capped = series["solver_residual"] >= tolerance
    if len(steps) < 2 or np.any(np.diff(steps) != 1):
        raise ValueError(f"{path}: rows are not one per step (run gf-shear with --observe-every 1)")
    p = series["pressure"]
    with np.errstate(divide="ignore", invalid="ignore"):
        values = {"p": p, "s/p": series["shear_stress"] / p, "T": series["temperature"]}
    return tolerance, steps, series["strain"], series["solver_residual"], capped, values


def spikes(prefix, x, k):
    """{prefix_p10, _p50, _p90}: quantiles of x_k/((x_(k-1) + x_(k+1))/2) over the steps k (NaN: none)."""
    q = np.quantile(2 * x[k] / (x[k - 1] + x[k + 1]), [0.1, 0.5, 0.9]) if len(k) else [np.nan] * 3
    return {f"{prefix}_p{p}": float(v) for p, v in zip((10, 50, 90), q)}


def analyse(path, from_strain):
    """Rows (dicts) of one run, one per observable."""
    tolerance, steps, strain, residual, capped, values = read_run(path)
    window = strain >= from_strain
    if window.sum() < MIN_ROWS:
        raise ValueError(f"{path}: {int(window.sum())} rows at strain >= {from_strain:g} (need {MIN_ROWS})")
    k = np.arange(len(steps))
    inner = window & (k >= 1) & (k < len(steps) - 1)
    before, after = np.roll(capped, 1), np.roll(capped, -1)
    isolated = np.where(inner & capped & ~before & ~after)[0]
    ordinary = np.where(inner & ~capped & ~before & ~after)[0]
    near_cap = np.convolve(capped.astype(float), np.ones(2 * NEAR + 1), mode="same") > 0
    nearby = ordinary[near_cap[ordinary]]
    cw = np.where(window & capped)[0]
    if len(cw) == 0:
        raise ValueError(f"{path}: no step at the cap at strain >= {from_strain:g}")
    converged = window & ~capped
    if not converged.any():
        raise ValueError(f"{path}: every step at strain >= {from_strain:g} is at the cap")
    rows = []
    for name in OBSERVABLES:
        x = values[name]
        if not np.all(np.isfinite(x[window])):
            raise ValueError(f"{path}: non-finite {name} in the window")
        ref = np.sort(x[converged])
        percentile = float(np.mean(np.searchsorted(ref, x[cw]) / len(ref)))
        mean_with, mean_without = float(np.mean(x[window])), float(np.mean(x[converged]))
        rows.append(
            {
                "run": path,
                "observable": name,
                "capped": len(cw),
                "isolated": len(isolated),
                "residual_median": float(np.median(residual[cw]) / tolerance),
                "residual_max": float(np.max(residual[cw]) / tolerance),
                "percentile": percentile,
                **spikes("spike_capped", x, isolated),
                **spikes("spike_nearby", x, nearby),
                **spikes("spike_ordinary", x, ordinary),
                "drop_effect": (mean_without - mean_with) / mean_with,
                "spike_effect": float(np.sum(x[isolated] - (x[isolated - 1] + x[isolated + 1]) / 2))
                / (float(window.sum()) * mean_with),
            }
        )
    return rows


COLUMNS = (
    "run",
    "observable",
    "capped",
    "isolated",
    "residual_median",
    "residual_max",
    "percentile",
    "spike_capped_p10",
    "spike_capped_p50",
    "spike_capped_p90",
    "spike_nearby_p10",
    "spike_nearby_p50",
    "spike_nearby_p90",
    "spike_ordinary_p10",
    "spike_ordinary_p50",
    "spike_ordinary_p90",
    "drop_effect",
    "spike_effect",
)


def cell(v):
    return v if isinstance(v, str) else f"{v:d}" if isinstance(v, (int, np.integer)) else f"{v:.4g}"


def main(argv=None):
    ap = Parser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", metavar="RUN.h5", help="gf-shear trajectories written with --observe-every 1")
    ap.add_argument("--from-strain", type=float, default=1.0, metavar="S", help="the window: rows at strain >= S (default 1)")
    ap.add_argument("--csv", metavar="FILE", help="also write the table to FILE (comment line, header, one row per run and observable)")
    a = ap.parse_args(argv)
    if not np.isfinite(a.from_strain) or a.from_strain < 0:
        ap.error("--from-strain must be a finite number >= 0")
    try:
        rows = [r for path in a.runs for r in analyse(path, a.from_strain)]
    except ValueError as e:
        print(f"unconverged_steps.py: error: {e}", file=sys.stderr)
        return 2
    lines = [",".join(COLUMNS)] + [",".join(cell(r[c]) for c in COLUMNS) for r in rows]
    print("\n".join(lines))
    if a.csv:
        command = " ".join(shlex.quote(x) for x in ["unconverged_steps.py", *(sys.argv[1:] if argv is None else argv)])
        outputs.write_text(a.csv, f"# {command}\n" + "\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
