#!/usr/bin/env python3
"""incline_bulk.py [--base-skip D] [--surface-skip D] --output TABLE.h5 RUN.h5...: the bulk of
gf-incline runs (thesis §4.3.2–4.4, Figs 4.8–4.10), one row per run, from each run's /profiles
(x- and time-averaged layers over its steady part, see gf-incline --help).

Surface height H (from the base centre line y = 0): the mobile mass per unit length over the
bulk density, H = Σm / (L_x ν_bulk) (areal grain density 1), iterated twice with the bulk.
Bulk layers: centre at least --base-skip mean diameters above the base and at least
--surface-skip mean diameters below H (the thesis: the invariants are not constant "close to
the bumpy grain boundary" nor "close to the free boundary", §4.3.2).

Per run (a run whose bulk layers do not all move faster than 0.05 √(g⟨R⟩) has flowing = 0
and NaN for everything below but ν):
- bulk values (Fig 4.10) of ν, s/p, γ̇⟨R⟩/√T, mT/p⟨R⟩²: the mean over the bulk layers, with
  the standard error of that mean from their scatter (<name>_error; not a time-sampling error)
  and the relative change across the bulk from a straight-line fit (<name>_drift: a test of
  "independent of y", Fig 4.9);
- momentum balance (eq. 4.7–4.9): the largest |Σ_yy/(g cos θ W) − 1| and |s/(g sin θ W) − 1|
  over the bulk layers, W the mass above per unit length (/profiles/weight_above = g W);
- the V_x profile: the Bagnold form V_x = V_s − c (H − y)^a fitted by least squares (a on a
  grid of 10⁻³ in [0.2, 4], V_s and c linear) to the bulk layers (velocity_exponent; a = 3/2
  is the thesis' "y^{3/2}", the Bagnold profile of Silbert et al.), the same on the layers
  from the base skip up to the last whose centre is below H (velocity_exponent_full, with
  its V_s = surface_velocity: the less rigid layers near the surface included), and the plain
  power law V_x ∝ y^b on the bulk layers (power_law_exponent), which is not 3/2 and shows why
  the depth below the surface is the variable to fit in.

Output (HDF5, atomically): /parameters (program, script_sha256, command_line, base_skip,
surface_skip); /runs/<column> [rows] (input, input_sha256, start, start_time, start_friction, angle, friction, restitution,
grains, layer_length, mean_radius, mean_mass, tau, gravity, time, steady, steady_from_tau,
steady_from_given, surface_height, bulk_layers, bulk_from, bulk_to, flowing); /bulk/<name>,
<name>_error, <name>_drift; /balance/{yy_max_deviation, xy_max_deviation};
/fit/{velocity_exponent, velocity_exponent_full, power_law_exponent, surface_velocity}.
Lengths in code units unless the name says diameters; velocities in √(g⟨R⟩).
"""
import argparse
import math
import os
import shlex
import sys

import h5py
import numpy as np

from granflow import outputs
from granflow.hdf5 import in_tau, read_attrs, sha256

PROFILE_NAMES = (
    "y",
    "packing_fraction",
    "velocity_x",
    "shear_rate",
    "temperature",
    "pressure",
    "shear_stress",
    "stress_xx",
    "stress_yy",
    "weight_above",
    "s_over_p",
    "inertial",
    "mT_over_pR2",
)
PARAMETERS = {
    "angle": float,
    "friction": float,
    "restitution": float,
    "grains": int,
    "tau": float,
    "gravity": float,
    "dt": float,
    "total_steps": int,
}
BULK = {"packing_fraction": "ν", "s_over_p": "s/p", "inertial": "γ̇⟨R⟩/√T", "mT_over_pR2": "mT/(p⟨R⟩²)"}
MIN_FLOW = 0.05  # a bulk layer slower than this (in √(g⟨R⟩)) does not flow
EXPONENTS = np.arange(0.2, 4.0 + 1e-9, 1e-3)


def read_run(path):
    """{"parameters", "profiles" (arrays), "attrs" (of /profiles)} of one gf-incline trajectory."""
    with h5py.File(path, "r") as f:
        if "profiles" not in f:
            raise ValueError("no /profiles (not a gf-incline trajectory?)")
        attrs = read_attrs(f["/parameters"])
        missing = [k for k in PARAMETERS if k not in attrs]
        if missing:
            raise ValueError(f"/parameters lacks {', '.join(missing)}")
        params = {k: t(attrs[k]) for k, t in PARAMETERS.items()}
        params["time"] = params["dt"] * params["total_steps"] / params["tau"]
        # What the run started from: a pack, or a frame of a parent run (a branch).
        params["start"] = os.path.basename(attrs.get("input", ""))
        # input_time is in the parent's unit (input_time_unit; code time before it existed).
        params["start_time"] = in_tau(
            float(attrs.get("input_time", 0.0)), attrs.get("input_time_unit", "T"), params["tau"]
        )
        params["start_friction"] = float(attrs.get("parent_friction", math.nan))
        g = f["/profiles"]
        prof = {k: g[k][...].astype(float) for k in PROFILE_NAMES}
        pattrs = read_attrs(g)
    # The start of the averaged part: steady_from_time in τ (time_unit "tau"), or in files
    # of code time steady_from_tau.
    steady_from = "steady_from_time" if pattrs.get("time_unit") == "tau" else "steady_from_tau"
    for k in ("mean_radius", "mean_mass", "layer_length", "bin", "steady", steady_from):
        if k not in pattrs:
            raise ValueError(f"/profiles lacks the attribute {k}")
    params.update(
        mean_radius=float(pattrs["mean_radius"]),
        mean_mass=float(pattrs["mean_mass"]),
        layer_length=float(pattrs["layer_length"]),
        steady=int(pattrs["steady"]),
        steady_from_tau=float(pattrs[steady_from]),
        steady_from_given=int(pattrs.get("steady_from_given", 0)),
    )
    return {"parameters": params, "profiles": prof, "bin": float(pattrs["bin"])}


def bulk_layers(run, base_skip, surface_skip):
    """(surface height H, indices of the bulk layers, bulk ν) — see the module text."""
    prm, prof = run["parameters"], run["profiles"]
    d = 2 * prm["mean_radius"]
    y, nu = prof["y"], prof["packing_fraction"]
    mass_per_length = prm["grains"] * prm["mean_mass"] / prm["layer_length"]
    finite = np.isfinite(nu)
    nu_bulk = float(np.nanmax(nu))
    for _ in range(3):
        height = mass_per_length / nu_bulk
        idx = np.flatnonzero(finite & (y >= base_skip * d) & (y <= height - surface_skip * d))
        if len(idx) == 0:
            break
        nu_bulk = float(np.mean(nu[idx]))
    height = mass_per_length / nu_bulk
    idx = np.flatnonzero(finite & (y >= base_skip * d) & (y <= height - surface_skip * d))
    return height, idx, nu_bulk


def mean_error_drift(y, v):
    """Mean of v over layers, standard error from their scatter, relative change across y."""
    v = np.asarray(v, dtype=float)
    mean = float(np.mean(v))
    if len(v) < 2:
        return mean, math.nan, math.nan
    err = float(np.std(v, ddof=1) / math.sqrt(len(v)))
    slope = np.polyfit(y, v, 1)[0]
    return mean, err, float(slope * (y[-1] - y[0]) / mean) if mean != 0 else math.nan


def fit_bagnold(y, v, height):
    """(a, V_s, c) of the least-squares fit v = V_s − c (height − y)^a over a in EXPONENTS."""
    y, v = np.asarray(y, dtype=float), np.asarray(v, dtype=float)
    if len(y) < 3:
        raise ValueError(f"the V_x fit needs at least 3 layers, got {len(y)}")
    depth = height - y
    if np.any(depth <= 0):
        raise ValueError("the V_x fit got a layer above the surface")
    best = (math.inf, math.nan, math.nan, math.nan)
    for a in EXPONENTS:
        x = np.vstack([np.ones_like(depth), -(depth**a)]).T
        coef, _, _, _ = np.linalg.lstsq(x, v, rcond=None)
        r = float(np.sum((x @ coef - v) ** 2))
        if r < best[0]:
            best = (r, a, coef[0], coef[1])
    return float(best[1]), float(best[2]), float(best[3])


def analyse_run(run, base_skip, surface_skip):
    """Row of the table for one run (dict of column -> value)."""
    prm, prof = run["parameters"], run["profiles"]
    d = 2 * prm["mean_radius"]
    y = prof["y"]
    height, idx, nu_bulk = bulk_layers(run, base_skip, surface_skip)
    if len(idx) < 2:
        raise ValueError(
            f"only {len(idx)} bulk layers between {base_skip} diameters above the base and "
            f"{surface_skip} below the surface (H = {height / d:.1f} diameters); lower "
            "--base-skip/--surface-skip or use a thicker layer"
        )
    row = {
        "surface_height": height,
        "bulk_layers": len(idx),
        "bulk_from": float(y[idx[0]]),
        "bulk_to": float(y[idx[-1]]),
    }
    scale = math.sqrt(prm["gravity"] * prm["mean_radius"])
    v = prof["velocity_x"] / scale
    # A layer that does not flow (θ < θ_c) has no defined rheology: NaN everywhere but ν.
    row["flowing"] = int(bool(np.all(np.isfinite([prof[n][idx] for n in BULK])) and np.all(v[idx] > MIN_FLOW)))
    if not row["flowing"]:
        for name in GROUPS["bulk"] + GROUPS["balance"] + GROUPS["fit"]:
            row[name] = math.nan
        row["packing_fraction"] = float(np.mean(prof["packing_fraction"][idx]))
        return row
    for name in BULK:
        row[name], row[name + "_error"], row[name + "_drift"] = mean_error_drift(y[idx], prof[name][idx])
    theta = math.radians(prm["angle"])
    w = prof["weight_above"][idx]
    row["yy_max_deviation"] = float(np.max(np.abs(prof["stress_yy"][idx] / (math.cos(theta) * w) - 1)))
    row["xy_max_deviation"] = float(np.max(np.abs(prof["shear_stress"][idx] / (math.sin(theta) * w) - 1)))
    fit = np.flatnonzero(np.isfinite(v) & (y >= base_skip * d) & (y < height))
    row["velocity_exponent_full"], row["surface_velocity"], _ = fit_bagnold(y[fit], v[fit], height)
    row["velocity_exponent"] = fit_bagnold(y[idx], v[idx], height)[0] if len(idx) >= 3 else math.nan
    positive = idx[v[idx] > 0]
    row["power_law_exponent"] = (
        float(np.polyfit(np.log(y[positive]), np.log(v[positive]), 1)[0]) if len(positive) >= 2 else math.nan
    )
    return row


def plot_input(doc, prog):
    """The command line of a one-run incline figure script (RUN.h5 OUTPUT.png, --base-skip,
    --surface-skip): returns (args, run, analysed row), or exits naming the run."""
    ap = argparse.ArgumentParser(description=doc)
    ap.add_argument("--base-skip", type=float, default=3.0)
    ap.add_argument("--surface-skip", type=float, default=8.0)
    ap.add_argument("input")
    ap.add_argument("output")
    args = ap.parse_args()
    try:
        run = read_run(args.input)
        row = analyse_run(run, args.base_skip, args.surface_skip)
    except (OSError, KeyError, ValueError) as exc:
        sys.exit(f"{prog}: {args.input}: {exc}")
    return args, run, row


RUN_COLUMNS = (
    "angle",
    "friction",
    "restitution",
    "grains",
    "layer_length",
    "mean_radius",
    "mean_mass",
    "tau",
    "gravity",
    "time",
    "steady",
    "steady_from_tau",
    "steady_from_given",
)
RUN_MEANINGS = {
    "steady_from_tau": "start (τ) of the averaged part: the /profiles attribute 'steady_from_time' "
    "('steady_from_tau' in files of code time)",
}
GROUPS = {
    "runs": ("surface_height", "bulk_layers", "bulk_from", "bulk_to", "flowing"),
    "bulk": tuple(n + s for n in BULK for s in ("", "_error", "_drift")),
    "balance": ("yy_max_deviation", "xy_max_deviation"),
    "fit": ("velocity_exponent", "velocity_exponent_full", "power_law_exponent", "surface_velocity"),
}
MEANINGS = {
    "flowing": f"1 if every bulk layer moves faster than {MIN_FLOW} √(g⟨R⟩) (else the other "
    "bulk and fit values are NaN but ν)",
    "surface_height": "H = Σm/(L_x ν_bulk), from the base centre line (code units)",
    "bulk_layers": "number of bulk layers",
    "bulk_from": "centre of the lowest bulk layer (code units)",
    "bulk_to": "centre of the highest bulk layer (code units)",
    "yy_max_deviation": "max over bulk layers of |Σ_yy/(g cos θ W) − 1| (eq. 4.8)",
    "xy_max_deviation": "max over bulk layers of |s/(g sin θ W) − 1| (eq. 4.9)",
    "velocity_exponent": "a of V_x = V_s − c (H − y)^a, bulk layers",
    "velocity_exponent_full": "a of V_x = V_s − c (H − y)^a, layers from the base skip to the surface",
    "surface_velocity": "V_s of the fit from the base skip to the surface, in √(g⟨R⟩)",
    "power_law_exponent": "b of V_x ∝ y^b, bulk layers",
}
# The unit string of each column with a unit; the others (velocities in √(g⟨R⟩) among them) are numbers.
UNITS = {
    "angle": "deg",
    "layer_length": "L",
    "mean_radius": "L",
    "mean_mass": "M",
    "tau": "T",
    "gravity": "L T-2",
    "time": "tau",
    "steady_from_tau": "tau",
    "start_time": "tau",
    "surface_height": "L",
    "bulk_from": "L",
    "bulk_to": "L",
}
for _n, _label in BULK.items():
    MEANINGS[_n] = f"{_label}: mean over the bulk layers"
    MEANINGS[_n + "_error"] = f"{_label}: standard error of that mean from the scatter of the bulk layers"
    MEANINGS[_n + "_drift"] = f"{_label}: relative change across the bulk (straight-line fit)"


def analyse(paths, base_skip, surface_skip):
    rows = []
    for path in paths:
        try:
            run = read_run(path)
            row = analyse_run(run, base_skip, surface_skip)
        except (OSError, KeyError, ValueError) as exc:
            raise ValueError(f"{path}: {exc}") from exc
        row.update({k: run["parameters"][k] for k in RUN_COLUMNS})
        row["input"], row["input_sha256"] = path, sha256(path)
        row.update({k: run["parameters"][k] for k in ("start", "start_time", "start_friction")})
        rows.append(row)
    return rows


def write_table(output, rows, base_skip, surface_skip, command_line):
    with outputs.table(
        output,
        os.path.abspath(__file__),
        command_line,
        {"base_skip": base_skip, "surface_skip": surface_skip},
        [(r["input"], r["input_sha256"]) for r in rows],
    ) as f:
        runs = f["runs"]
        outputs.text_dataset(runs, "start", [r["start"] for r in rows])
        runs["start"].attrs["meaning"] = (
            "file the run started from (its /parameters input): a pack or, for a " "branch, the parent run"
        )
        for col in RUN_COLUMNS:
            outputs.column(runs, col, [r[col] for r in rows], UNITS.get(col, "1"),
                           RUN_MEANINGS.get(col, f"the run's parameter or /profiles attribute '{col}'"), dtype=None)
        for col, meaning in (
            ("start_time", "time (τ) of the parent's frame the run started from (0: a pack)"),
            ("start_friction", "friction of the parent run (NaN: started from a pack)"),
        ):
            outputs.column(runs, col, [r[col] for r in rows], UNITS.get(col, "1"), meaning, dtype=None)
        for group, names in GROUPS.items():
            g = f.require_group(group)
            for name in names:
                outputs.column(g, name, [r[name] for r in rows], UNITS.get(name, "1"), MEANINGS[name], dtype=None)


def read_table(path):
    """{group: {name: array}} plus "parameters"."""
    return outputs.read_table(path, ("runs", "bulk", "balance", "fit"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument(
        "--base-skip", type=float, default=3.0, help="bulk starts this many mean diameters above " "the base (3)"
    )
    ap.add_argument(
        "--surface-skip", type=float, default=8.0, help="bulk ends this many mean diameters below " "the surface (8)"
    )
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("runs", nargs="+", help="gf-incline trajectories")
    args = ap.parse_args()
    try:
        rows = analyse(args.runs, args.base_skip, args.surface_skip)
    except ValueError as exc:
        print(f"incline_bulk.py: {exc}", file=sys.stderr)
        sys.exit(2)
    write_table(args.output, rows, args.base_skip, args.surface_skip, shlex.join(sys.argv))


if __name__ == "__main__":
    main()
