#!/usr/bin/env python3
"""critical_angle.py [--window T] [--rest-velocity V] --output TABLE.h5 RUN.h5...: the critical
angle θ_c of incline flow (thesis §4.3.1) from gf-incline runs at several angles (same grains,
friction and start), "the angle below which the average velocity fluctuates around zero".

Per run, the flow rate (/observables/flow_rate: the mass-weighted mean v_x of the mobile
grains, in units of √(g⟨R⟩)) over the last --window τ of the run (τ = √(⟨R⟩/g)):
- V̄, its mean, with the standard error σ from Flyvbjerg–Petersen blocking (steady_state.py);
- the change between the window's halves, Δ = V̄₂ − V̄₁, with its error σ_Δ (each half blocked).
Classification:
- "rest": |V̄| ≤ max(3σ, --rest-velocity): the mean velocity is zero within its fluctuations
  (Contact Dynamics keeps some motion below θ_c, the thesis notes; --rest-velocity, default
  0.02 √(g⟨R⟩), counts a creep that slow as rest);
- "steady": V̄ > that and |Δ| ≤ max(3σ_Δ, --drift·V̄) (default 15 %: the flow rate of a
  layer of 10³ grains wanders by ±5 % over tens of τ, more than its blocking error says:
  at 10°, μ = 0 the halves of the last 100 τ differed by 6 %, 7σ);
- "accelerating" (Δ > 0) or "decelerating" (Δ < 0) otherwise. An accelerating flow flows
  (θ ≥ θ_c); a decelerating one is on its way to rest or to a slower flow the run did not
  reach, so it does not count as steady flow.
θ_c lies in the bracket (θ_below, θ_above]: θ_above the lowest angle from which every angle
of the sweep flows (steady or accelerating), θ_below the highest angle below it that does
not; θ_c is reported as the midpoint, ± half the bracket. `consistent` = 0 when an angle
below θ_below flows (non-monotonic sweep: the bracket is then the upper one). With no
flowing angle, θ_below is the highest angle and θ_above = inf; with every angle flowing,
θ_below = -inf.

Output (HDF5, atomically): /parameters (program, script_sha256, command_line, window,
rest_velocity, drift); /runs/<column> [rows, by angle]: input, input_sha256, angle, friction,
restitution, mean_velocity, mean_velocity_error, drift, drift_error, state (text),
flowing (1/0); /critical_angle attrs theta_c, theta_below, theta_above, half_width, consistent.
"""
import argparse
import math
import os
import shlex
import sys

import h5py
import numpy as np

from analysis import steady_state as ss
from granflow import outputs
from granflow.hdf5 import in_tau, read_attrs, sha256, time_unit

FLOWING_STATES = ("steady", "accelerating")


def read_flow(path):
    """(parameters, time in τ, flow rate in √(g⟨R⟩)) of one gf-incline trajectory."""
    with h5py.File(path, "r") as f:
        prm = read_attrs(f["/parameters"])
        missing = [k for k in ("angle", "friction", "restitution", "tau", "gravity", "mean_radius") if k not in prm]
        if missing:
            raise ValueError(f"/parameters lacks {', '.join(missing)}")
        if "observables/flow_rate" not in f:
            raise ValueError("no /observables/flow_rate (not a gf-incline trajectory?)")
        time = f["observables/flow_rate/time"][...].astype(float)
        unit = time_unit(f["observables/flow_rate/time"])
        value = f["observables/flow_rate/value"][...].astype(float)
    params = {k: float(prm[k]) for k in ("angle", "friction", "restitution", "tau", "gravity", "mean_radius")}
    return params, in_tau(time, unit, params["tau"]), value / math.sqrt(params["gravity"] * params["mean_radius"])


def classify(time, velocity, window, rest_velocity, drift):
    """(state, V̄, σ, Δ, σ_Δ) over the last `window` of the series (see the module text)."""
    keep = time >= time[-1] - window
    v = velocity[keep]
    if len(v) < 2 * ss.MIN_SAMPLES:
        raise ValueError(f"only {len(v)} flow-rate samples in the last {window:g} τ (need {2 * ss.MIN_SAMPLES})")
    if not np.all(np.isfinite(v)):
        raise ValueError("non-finite flow rate")
    mean = float(np.mean(v))
    err = ss.blocking_error(v)[0]
    change, change_err = ss.halves_change(v)
    if abs(mean) <= max(3 * err, rest_velocity):
        state = "rest"
    elif abs(change) <= max(3 * change_err, drift * abs(mean)):
        state = "steady"
    else:
        state = "accelerating" if change > 0 else "decelerating"
    return state, mean, err, change, change_err


def bracket(angles, flowing):
    """(θ_below, θ_above, consistent) for angles sorted ascending (see the module text)."""
    angles, flowing = np.asarray(angles, dtype=float), np.asarray(flowing, dtype=bool)
    if len(angles) == 0:
        raise ValueError("no runs")
    if not flowing.any():
        return float(angles[-1]), math.inf, True
    # Lowest index from which every angle flows.
    k = len(angles)
    while k > 0 and flowing[k - 1]:
        k -= 1
    above = float(angles[k])
    if k == 0:
        return -math.inf, above, True
    below = float(angles[k - 1])
    return below, above, not flowing[:k].any()


def analyse(paths, window, rest_velocity, drift):
    rows = []
    for path in paths:
        try:
            prm, time, velocity = read_flow(path)
            state, mean, err, change, change_err = classify(time, velocity, window, rest_velocity, drift)
        except (OSError, KeyError, ValueError) as exc:
            raise ValueError(f"{path}: {exc}") from exc
        rows.append(
            {
                "input": path,
                "input_sha256": sha256(path),
                "angle": prm["angle"],
                "friction": prm["friction"],
                "restitution": prm["restitution"],
                "mean_velocity": mean,
                "mean_velocity_error": err,
                "drift": change,
                "drift_error": change_err,
                "state": state,
                "flowing": int(state in FLOWING_STATES),
            }
        )
    frictions = {r["friction"] for r in rows}
    if len(frictions) > 1:
        raise ValueError(f"runs with different friction {sorted(frictions)}: one sweep at a time")
    rows.sort(key=lambda r: r["angle"])
    below, above, consistent = bracket([r["angle"] for r in rows], [r["flowing"] for r in rows])
    if math.isfinite(below) and math.isfinite(above):
        result = {"theta_c": 0.5 * (below + above), "half_width": 0.5 * (above - below)}
    else:
        result = {"theta_c": math.nan, "half_width": math.nan}
    result.update(theta_below=below, theta_above=above, consistent=int(consistent))
    return rows, result


MEANINGS = {
    "angle": "incline angle θ (degrees)",
    "friction": "μ",
    "restitution": "e",
    "mean_velocity": "mean flow rate over the window, in √(g⟨R⟩)",
    "mean_velocity_error": "its standard error (Flyvbjerg–Petersen blocking)",
    "drift": "mean of the window's second half minus its first half, in √(g⟨R⟩)",
    "drift_error": "its standard error",
    "state": "rest, steady, accelerating or decelerating",
    "flowing": "1 for steady or accelerating flow",
}


def write_table(output, rows, result, args, command_line):
    parameters = {"window": args["window"], "rest_velocity": args["rest_velocity"], "drift": args["drift"]}
    with outputs.table(
        output, os.path.abspath(__file__), command_line, parameters, [(r["input"], r["input_sha256"]) for r in rows]
    ) as f:
        runs = f["runs"]
        outputs.text_dataset(runs, "state", [r["state"] for r in rows])
        runs["state"].attrs["meaning"] = MEANINGS["state"]
        for col in MEANINGS:
            if col != "state":
                # Velocities are in √(g⟨R⟩), numbers: only the angle has a unit.
                outputs.column(runs, col, [r[col] for r in rows], "deg" if col == "angle" else "1", MEANINGS[col],
                               dtype=None)
        g = f.create_group("critical_angle")
        g.attrs.update(result)
        g.attrs["meaning"] = (
            "θ_c in (theta_below, theta_above] degrees, theta_c the midpoint ± half_width; "
            "consistent = 0 if an angle below theta_below flows"
        )


def read_table(path):
    table = outputs.read_table(path, ("runs",))
    with h5py.File(path, "r") as f:
        table["critical_angle"] = read_attrs(f["critical_angle"])
    return table


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--window", type=float, default=100.0, help="analyse the last T τ of each run (100)")
    ap.add_argument(
        "--rest-velocity",
        type=float,
        default=0.02,
        help="a mean flow rate below this, in √(g⟨R⟩), counts as rest (0.02)",
    )
    ap.add_argument(
        "--drift",
        type=float,
        default=0.15,
        help="relative change between the window's halves still taken as steady (0.15)",
    )
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("runs", nargs="+", help="gf-incline trajectories at several angles, one friction")
    args = ap.parse_args()
    for name in ("window", "rest_velocity", "drift"):
        if not getattr(args, name) > 0:
            ap.error(f"--{name.replace('_', '-')} must be > 0")
    try:
        rows, result = analyse(args.runs, args.window, args.rest_velocity, args.drift)
    except ValueError as exc:
        print(f"critical_angle.py: {exc}", file=sys.stderr)
        sys.exit(2)
    write_table(args.output, rows, result, vars(args), shlex.join(sys.argv))
    below, above = result["theta_below"], result["theta_above"]
    print(
        f"critical_angle.py: θ_c in ({below:g}°, {above:g}°]"
        + (f" = {result['theta_c']:g}° ± {result['half_width']:g}°" if math.isfinite(result["theta_c"]) else ""),
        file=sys.stderr,
    )


if __name__ == "__main__":
    main()
