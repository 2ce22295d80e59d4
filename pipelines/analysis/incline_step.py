#!/usr/bin/env python3
"""incline_step.py --default-step H --output OUT.h5 [--markdown OUT.md] [--window T] TABLE.h5...:
the incline's observables (Figs 4.8-4.10) against its time step dt/τ, with the convergence
study's classes.

Each TABLE is an incline_bulk.py table (ch4_incline.h5) whose runs share one time step, read from
the runs' own /parameters (dt/tau); tables at one step are refused. Per angle and friction, over
the steps: the bulk ν, s/p, γ̇⟨R⟩/√T, mT/(p⟨R⟩²) with their errors (incline_bulk.py's: the scatter
of the bulk layers), the exponents of the velocity profile (velocity_exponent,
velocity_exponent_full, power_law_exponent; no error), the surface velocity V_s, and the flow
rate V̄ (the mass-weighted mean v_x of the mobile grains over the run's last --window τ, with
its blocking error; critical_angle.py's estimator), each classed by convergence.classify
(converged, converging with its limit, regularisation-dependent, unsettled).

Output (HDF5, written atomically, with the provenance of every analysis table): /parameters
(program, script_sha256, command_line, default_step, window); /runs/input, input_sha256 (the
tables); /series/<column> [rows], one per (angle, friction, observable, step): angle, friction,
step, observable, value, error; /classes/<column> [rows], one per (angle, friction, observable):
angle, friction, observable, class and the numbers of convergence.classify.
"""
import argparse
import math
import shlex
import sys

import h5py
import numpy as np

from analysis import convergence
from analysis import critical_angle
from analysis import incline_bulk
from granflow import outputs
from granflow.hdf5 import read_attrs, sha256

# (key, label, group, dataset, error dataset or None)
OBSERVABLES = (
    ("nu", "bulk ν", "bulk", "packing_fraction", "packing_fraction_error"),
    ("s_over_p", "bulk s/p", "bulk", "s_over_p", "s_over_p_error"),
    ("inertial", "bulk γ̇⟨R⟩/√T", "bulk", "inertial", "inertial_error"),
    ("mT_over_pR2", "bulk mT/(p⟨R⟩²)", "bulk", "mT_over_pR2", "mT_over_pR2_error"),
    ("velocity_exponent", "a of V_s − c(H − y)^a, bulk", "fit", "velocity_exponent", None),
    ("velocity_exponent_full", "a, base to surface", "fit", "velocity_exponent_full", None),
    ("power_law_exponent", "b of V ∝ y^b", "fit", "power_law_exponent", None),
    ("surface_velocity", "V_s/√(g⟨R⟩)", "fit", "surface_velocity", None),
)
FLOW = ("flow_rate", "flow rate V̄/√(g⟨R⟩)")
CLASS_COLUMNS = ("steps", "span", "default_value", "default_error", "finest_step", "finest_value", "finest_error",
                 "limit", "limit_error", "limit_exponent", "step_1pct", "exponent", "exponent_error")


def run_step(path):
    """The time step of a gf-incline run in τ (dt/tau of its /parameters)."""
    with h5py.File(path, "r") as f:
        a = read_attrs(f["parameters"])
    return float(f"{float(a['dt']) / float(a['tau']):.12g}")


def read_series(paths, window):
    """{(angle, friction): {step: {key: (value, error)}}} over the tables, one step per table."""
    series, seen = {}, {}
    for path in paths:
        table = incline_bulk.read_table(path)
        inputs = [str(p.decode() if isinstance(p, bytes) else p) for p in table["runs"]["input"]]
        steps = {run_step(p) for p in inputs}
        if len(steps) != 1:
            raise ValueError(f"{path}: its runs have {len(steps)} time steps ({sorted(steps)}); one is needed")
        h = steps.pop()
        if h in seen:
            raise ValueError(f"{path}: a second table at time step {h:g} τ (the first: {seen[h]})")
        seen[h] = path
        for i, run in enumerate(inputs):
            key = (float(table["runs"]["angle"][i]), float(table["runs"]["friction"][i]))
            entry = series.setdefault(key, {}).setdefault(h, {})
            for obs, _label, group, name, error in OBSERVABLES:
                value = float(table[group][name][i])
                err = float(table[group][error][i]) if error else math.nan
                entry[obs] = (value, err)
            _params, time, velocity = critical_angle.read_flow(run)
            _state, mean, err, _change, _change_err = critical_angle.classify(time, velocity, window, 0.0, 1.0)
            entry[FLOW[0]] = (mean, err)
    if len(seen) < 2:
        raise ValueError("need tables at two time steps or more")
    return series


def markdown(series, classes, default_step, labels):
    lines = []
    for key in sorted(series):
        steps = sorted(series[key], reverse=True)
        lines += [f"### θ = {key[0]:g}°, μ = {key[1]:g}", ""]
        head = ["observable"] + [f"dt = {h:g} τ" + (" (default)" if math.isclose(h, default_step, rel_tol=1e-9) else "")
                                 for h in steps] + ["class"]
        lines += ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        for obs, label in labels:
            cells = [convergence.fmt(*series[key][h][obs]) for h in steps]
            text = convergence.class_text(classes[key][obs]).replace("γ̇dt ≈", "dt/τ ≈").replace("(γ̇dt)^", "(dt)^")
            lines.append(f"| {label} | " + " | ".join(cells) + f" | {text} |")
        lines.append("")
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--default-step", type=float, required=True, help="the reproduction's time step, in τ")
    ap.add_argument("--window", type=float, default=200.0, help="τ at the end of each run for the flow rate (200)")
    ap.add_argument("-o", "--output", required=True, help="HDF5 table to write")
    ap.add_argument("--markdown", help="also write the tables as Markdown here")
    ap.add_argument("tables", nargs="+", help="incline_bulk.py tables, one per time step")
    args = ap.parse_args(argv)
    if not (math.isfinite(args.default_step) and args.default_step > 0):
        ap.error(f"--default-step: must be a positive number (got {args.default_step})")
    if not (math.isfinite(args.window) and args.window > 0):
        ap.error(f"--window: must be a positive number (got {args.window})")
    try:
        series = read_series(args.tables, args.window)
        if not any(math.isclose(h, args.default_step, rel_tol=1e-9) for s in series.values() for h in s):
            raise ValueError(f"--default-step {args.default_step:g}: no table at it")
    except (OSError, KeyError, ValueError) as error:
        print(f"incline_step.py: {error}", file=sys.stderr)
        return 2
    labels = [(o[0], o[1]) for o in OBSERVABLES] + [FLOW]
    classes = {
        key: {
            obs: convergence.classify(
                list(by_step), [by_step[h][obs][0] for h in by_step], [by_step[h][obs][1] for h in by_step],
                args.default_step,
            )
            for obs, _ in labels
        }
        for key, by_step in series.items()
    }
    with outputs.table(
        args.output, __file__, shlex.join(sys.argv), {"default_step": args.default_step, "window": args.window},
        [(p, sha256(p)) for p in args.tables],
    ) as f:
        cols = {k: [] for k in ("angle", "friction", "step", "observable", "value", "error")}
        for key in sorted(series):
            for h in sorted(series[key], reverse=True):
                for obs, _ in labels:
                    for name, v in zip(cols, (*key, h, obs, *series[key][h][obs])):
                        cols[name].append(v)
        # Every observable is a number (velocities in √(g⟨R⟩), the step dt/τ); the angle is in degrees.
        outputs.column_group(f, "series", cols, {c: "deg" if c == "angle" else "1" for c in cols})
        rows = [(key, obs, classes[key][obs]) for key in sorted(classes) for obs, _ in labels]
        ccols = {
            "angle": [k[0] for k, _, _ in rows],
            "friction": [k[1] for k, _, _ in rows],
            "observable": [o for _, o, _ in rows],
            "class": [c["class"] for _, _, c in rows],
            **{column: [c[column] for _, _, c in rows] for column in CLASS_COLUMNS},
        }
        outputs.column_group(f, "classes", ccols, {c: "deg" if c == "angle" else "1" for c in ccols})
    if args.markdown:
        outputs.write_text(args.markdown, markdown(series, classes, args.default_step, labels))
    return 0


if __name__ == "__main__":
    sys.exit(main())
