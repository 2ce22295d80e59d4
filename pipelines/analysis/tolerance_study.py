#!/usr/bin/env python3
"""tolerance_study.py --default-tolerance TOL [--sigmas K] --output OUT.h5 [--csv OUT.csv] TABLE.h5...:
observables of frictional flows against the solver tolerance (gf-shear --tolerance, Υ = tolerance/dt),
each looser tolerance compared with the default one.

Inputs are per-run tables of the tolerance study (pipelines/friction_tolerance.mk): steady_state.py
(p, s/p, T), gf-network (z) and sliding_share.py (the share of sliding contacts), told apart by
their /parameters `program`. Each row is matched to its run by /runs/input; the run's own
/parameters give ν, the seed and the tolerance, and every run must share N, e, μ and γ̇dt.

For each (ν, seed, observable) and tolerance t: the value Q(t) ± σ(t) (the tables' errors:
blocking, delta method), the difference d = Q(t) − Q(default) and d in combined errors,
d/√(σ(t)² + σ(default)²). Verdict per observable: "moves" when some looser tolerance's |d| exceeds
K (default 2) combined errors at some ν and seed, else "does not move"; "undecided" when no
tolerance moves it but some difference has no finite error.

Output (HDF5, written atomically): /parameters (program, script_sha256, command_line,
default_tolerance, sigmas, grains, restitution, friction, step); /runs/input, input_sha256;
/series/<column> [rows], one row per (ν, seed, observable, tolerance): packing_fraction, seed,
observable, label, unit, tolerance (L: residual velocity × dt), value, error, difference,
combined_error (in the row's unit, the string column `unit`), sigmas (d in combined errors,
"1"), verdict (the observable's); /verdicts/<column> [observables]: observable, label, verdict,
max_sigmas (the largest |d| in combined errors), worst_packing_fraction, worst_seed,
worst_tolerance (where it is). --csv: /series as CSV, one line per row after a comment line.
Bad input (no such table, a table of another program, runs differing in N, e, μ or γ̇dt, a
(ν, seed) without the default tolerance, fewer than two tolerances): exit 2, one line, nothing written.
"""
import argparse
import csv
import io
import math
import os
import shlex
import sys

import h5py
import numpy as np

from granflow import outputs
from granflow.hdf5 import read_attrs, read_dataset, sha256, text

# (key, label, program, dataset, error dataset)
OBSERVABLES = (
    ("p", "p/(mγ̇²)", "steady_state.py", "steady/pressure_scaled", "steady/pressure_scaled_error"),
    ("s_over_p", "s/p", "steady_state.py", "steady/s_over_p", "steady/s_over_p_error"),
    ("T", "T/(γ̇²⟨R⟩²)", "steady_state.py", "steady/temperature_scaled", "steady/temperature_scaled_error"),
    ("z", "z (age ≥ 2)", "gf-network", "runs/coordination", "runs/coordination_error"),
    ("sliding", "sliding share", "sliding_share.py", "runs/sliding_share", "runs/sliding_share_error"),
)
PROGRAMS = {o[2] for o in OBSERVABLES}
TOLERANCE_DIGITS = 12
SERIES_COLUMNS = ("packing_fraction", "seed", "observable", "label", "unit", "tolerance", "value", "error",
                  "difference", "combined_error", "sigmas", "verdict")


class Parser(argparse.ArgumentParser):
    def error(self, message):
        print(f"tolerance_study.py: error: {message}", file=sys.stderr)
        sys.exit(2)


def run_parameters(run_path, cache):
    """((ν, seed, tolerance), (grains, e, μ, γ̇dt)) of a gf-shear run, from its /parameters."""
    if run_path not in cache:
        with h5py.File(run_path, "r") as f:
            a = read_attrs(f["parameters"])
        step = abs(float(a["rate"])) * float(a["dt"])
        cache[run_path] = (
            (round(float(a["packing_fraction"]), 6), int(a["seed"]),
             float(f"{float(a['tolerance']):.{TOLERANCE_DIGITS}g}")),
            (int(a["grains"]), round(float(a["restitution"]), 6), round(float(a["friction"]), 6),
             float(f"{step:.{TOLERANCE_DIGITS}g}")),
        )
    return cache[run_path]


def read_tables(paths):
    """({(ν, seed, tolerance): {observable: (value, error)}}, {observable: unit}, (grains, e, μ, step));
    ValueError on a table of another program, an observable without a unit or in two units, or runs
    that differ in N, e, μ or γ̇dt."""
    cache, rows, units, common = {}, {}, {}, {}
    for path in paths:
        with h5py.File(path, "r") as f:
            program = text(read_attrs(f["parameters"]).get("program", ""))
            if program not in PROGRAMS:
                raise ValueError(f"{path}: a table of '{program}', not of " + ", ".join(sorted(PROGRAMS)))
            inputs = read_dataset(f["runs/input"])
            base = os.path.dirname(os.path.abspath(path))
            for i, run in enumerate(inputs):
                run_path = run if os.path.isabs(run) or os.path.exists(run) else os.path.join(base, run)
                key, fixed = run_parameters(run_path, cache)
                common.setdefault(fixed, run_path)
                entry = rows.setdefault(key, {})
                for obs, _label, prog, name, error in OBSERVABLES:
                    if prog != program:
                        continue
                    if name not in f:
                        raise ValueError(f"{path}: no {name}")
                    if "unit" not in f[name].attrs:
                        raise ValueError(f"{path}: {name} has no unit attribute")
                    unit = text(f[name].attrs["unit"])
                    if units.setdefault(obs, unit) != unit:
                        raise ValueError(f"{path}: {name} is in {unit}, other tables give {obs} in {units[obs]}")
                    value = float(np.atleast_1d(f[name][()])[i])
                    err = float(np.atleast_1d(f[error][()])[i]) if error in f else math.nan
                    entry[obs] = (value, err)
    if len(common) > 1:
        (a, pa), (b, pb) = list(common.items())[:2]
        raise ValueError(f"the runs differ in (N, e, μ, γ̇dt): {a} ({pa}) against {b} ({pb})")
    if not common:
        raise ValueError("no runs in the tables")
    return rows, units, next(iter(common))


def compare(rows, default_tolerance, sigmas):
    """(series rows as dicts, {observable: verdict dict}) of the rows of read_tables; ValueError
    when a (ν, seed) lacks the default tolerance or has no other."""
    series, verdicts = [], {}
    labels = {o[0]: o[1] for o in OBSERVABLES}
    points = sorted({(nu, seed) for nu, seed, _ in rows})
    for nu, seed in points:
        tolerances = sorted(t for n, s, t in rows if (n, s) == (nu, seed))
        default = next((t for t in tolerances if math.isclose(t, default_tolerance, rel_tol=1e-9)), None)
        if default is None:
            raise ValueError(f"ν = {nu:g}, seed {seed}: no run at the default tolerance {default_tolerance:g}")
        if len(tolerances) < 2:
            raise ValueError(f"ν = {nu:g}, seed {seed}: no tolerance other than the default")
        for obs, *_ in OBSERVABLES:
            if obs not in rows[(nu, seed, default)]:
                continue
            q0, s0 = rows[(nu, seed, default)][obs]
            v = verdicts.setdefault(obs, {"observable": obs, "label": labels[obs], "max_sigmas": 0.0,
                                          "worst_packing_fraction": math.nan, "worst_seed": -1,
                                          "worst_tolerance": math.nan, "unknown": False})
            for t in tolerances:
                if obs not in rows[(nu, seed, t)]:
                    continue
                q, s = rows[(nu, seed, t)][obs]
                d = q - q0
                combined = math.hypot(s, s0) if t != default else 0.0
                z = 0.0 if t == default else (d / combined if combined > 0 else (0.0 if d == 0 else math.nan))
                if t != default:
                    if not math.isfinite(z):
                        v["unknown"] = True
                    elif abs(z) > v["max_sigmas"]:
                        v.update(max_sigmas=abs(z), worst_packing_fraction=nu, worst_seed=seed, worst_tolerance=t)
                series.append({"packing_fraction": nu, "seed": seed, "observable": obs, "label": labels[obs],
                               "tolerance": t, "value": q, "error": s, "difference": d,
                               "combined_error": combined, "sigmas": z})
    for v in verdicts.values():
        v["verdict"] = ("moves" if v["max_sigmas"] > sigmas else "undecided" if v["unknown"] else "does not move")
    for r in series:
        r["verdict"] = verdicts[r["observable"]]["verdict"]
    return series, verdicts


def write_csv(path, series, units, default_tolerance, sigmas):
    fh = io.StringIO()
    fh.write(f"# tolerance_study.py: differences from the default tolerance {default_tolerance:g}; "
             f"'moves' beyond {sigmas:g} combined errors\n")
    w = csv.writer(fh, lineterminator="\n")
    w.writerow(SERIES_COLUMNS)

    def number(x):
        return f"{x:.6g}" if np.isfinite(x) else ""

    for r in series:
        w.writerow([f"{r['packing_fraction']:.3f}", r["seed"], r["observable"], r["label"], units[r["observable"]],
                    f"{r['tolerance']:g}", *(number(r[k]) for k in ("value", "error", "difference",
                                                                      "combined_error", "sigmas")), r["verdict"]])
    outputs.write_text(path, fh.getvalue())


def main():
    ap = Parser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--default-tolerance", type=float, default=1e-10, help="the tolerance compared with (1e-10)")
    ap.add_argument("--sigmas", type=float, default=2.0, help="'moves' beyond this many combined errors (2)")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--csv", help="also write /series as CSV here")
    ap.add_argument("tables", nargs="+", help="per-run tables of steady_state.py, gf-network, sliding_share.py")
    args = ap.parse_args()
    if not args.default_tolerance > 0:
        ap.error("--default-tolerance must be positive")
    if not args.sigmas > 0:
        ap.error("--sigmas must be positive")
    for path in args.tables:
        if not os.path.isfile(path):
            ap.error(f"{path}: no such table")
    for out in (args.output, args.csv):
        if out and any(os.path.abspath(out) == os.path.abspath(t) for t in args.tables):
            ap.error(f"{out}: the output is also an input")
    try:
        rows, units, (grains, e, mu, step) = read_tables(args.tables)
        series, verdicts = compare(rows, args.default_tolerance, args.sigmas)
    except (OSError, KeyError, ValueError) as exc:
        ap.error(str(exc).splitlines()[0] if str(exc) else type(exc).__name__)
    params = {"default_tolerance": args.default_tolerance, "sigmas": args.sigmas, "grains": grains,
              "restitution": e, "friction": mu, "step": step}
    inputs = [(p, sha256(p)) for p in args.tables]
    with outputs.table(args.output, os.path.abspath(__file__), shlex.join(sys.argv), params, inputs) as f:
        cols = {c: [] for c in SERIES_COLUMNS}
        for r in series:
            for c in SERIES_COLUMNS:
                cols[c].append(units[r["observable"]] if c == "unit" else r[c])
        in_row_unit = ("value", "error", "difference", "combined_error")
        col_units = {c: "unit" if c in in_row_unit else "L" if c == "tolerance" else "1" for c in cols}
        outputs.column_group(f, "series", cols, col_units, integers=("seed",))
        order = [o[0] for o in OBSERVABLES if o[0] in verdicts]
        vcols = {c: [verdicts[o][c] for o in order]
                 for c in ("observable", "label", "verdict", "max_sigmas", "worst_packing_fraction", "worst_seed",
                           "worst_tolerance")}
        outputs.column_group(f, "verdicts", vcols, {c: "L" if c == "worst_tolerance" else "1" for c in vcols},
                             integers=("worst_seed",))
    if args.csv:
        write_csv(args.csv, series, units, args.default_tolerance, args.sigmas)
    return 0


if __name__ == "__main__":
    sys.exit(main())
