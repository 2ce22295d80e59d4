#!/usr/bin/env python3
"""steady_state.py [--from-strain S] [--detect-transient] --output TABLE.h5 RUN.h5...:
steady-state averages of gf-shear trajectories (thesis §4.2.2, Figs 4.2-4.6), one row per run.

Averages. gf-shear records every observable at a constant strain interval (every step
by default), so a steady value is the plain mean over the rows of the steady part. It
starts at --from-strain (default 0.5: the thesis finds steady flow "by a shear of
approximately 0.5", line 377, at ν = 0.8) or, with --detect-transient (the pipelines use
it), later where the run's own transient says so: MSER (White, Simulation 69, 323
(1997), as gf-incline applies it) on TRANSIENT_BLOCKS block means of T and of p each
picks the truncation d <= n/2 minimising the squared standard error of what is left, and
the later of the two wins. Dilute flows sheared from rest heat up for many strain units
(T still rises at strain 5 below ν = 0.6 at N = 1000 and e = 0.5, up to strain ~15 at
ν = 0.3), so a fixed 0.5 would average a transient there; gf-correlate
--detect-transient applies the same rule. Whether what is averaged is stationary is
checked: the means of T and p over its first and second halves, with
blocking errors, may differ by at most STATIONARY_SIGMAS combined errors (halves_z is the
larger difference, in errors; a run failing it is marked, not dropped). Ratios and
the dimensionless groups are ratios of means (p, s, T are means first, then combined),
never means of instantaneous ratios, which large force fluctuations would bias.

Error bars: the standard error of the mean from Flyvbjerg-Petersen blocking
(J. Chem. Phys. 91, 461 (1989)): the series is repeatedly replaced by the means of
neighbouring pairs; the variance of the block means divided by (blocks - 1) grows with
the block length until blocks are longer than the correlation time, then stays flat.
The plateau is found automatically with Jonsson's test (Phys. Rev. E 98, 043304
(2018)): the first level from which the lag-1 autocorrelations of all further levels
are compatible with zero (chi-squared test at 99 %); the error is read one level
higher (blocks twice as long), which halves the bias left by the residual correlation
at the first level. On AR(1) series the result is low by at most 15 % when the steady
part spans 50 integrated correlation times, 10 % at 100 and 3 % beyond 1000. Errors
are read only from levels with at least 16 blocks; when no such level passes the
test, the estimate of the longest such blocks is kept and flagged (<name>_plateau = 0):
it is then a lower bound, and the run is too short for its correlation time.
Errors of ratios and of the dimensionless groups come from the same blocking applied
to their linearisation Q * sum_k a_k (x_k(t) - <x_k>)/<x_k> for Q = c * prod_k <x_k>^a_k,
which keeps the correlations between numerator and denominator.

Output (HDF5, written atomically): /parameters (program, script_sha256, command_line,
from_strain, detect_transient, error_method); /runs/<column> [rows] with the run's input
path and SHA-256, packing_fraction, restitution, tangential_restitution, friction, rate,
strain_step, strain, dt, grains, seed, mean_radius, mean_mass, samples, steady_from (the
strain the average starts at), halves_z, stationary; /steady/<name>,
/steady/<name>_error, /steady/<name>_plateau [rows] for every name of QUANTITIES;
/diagnostics/{solver_iterations_mean, solver_residual_max, max_overlap_max} over the
steady part. Every dataset carries `meaning` and `unit` (H5MD) attributes; run columns' meanings name
the gf-shear parameter they copy.
"""
import argparse
import math
import os
import shlex
import sys

import h5py
import numpy as np

from granflow import outputs
from granflow.hdf5 import sha256
from granflow import statistics

ERROR_METHOD = (
    "standard error of the mean by Flyvbjerg-Petersen blocking, one level above the "
    "plateau found by Jonsson's test (99 %), at least 16 blocks; ratios and groups by "
    "blocking their linearisation"
)
MIN_SAMPLES = 32  # steady rows a run must have
TRANSIENT_BLOCKS = 100  # block means MSER looks at (fewer for shorter runs: a row each)
STATIONARY_SIGMAS = 3  # largest difference between the halves' means, in combined errors
MIN_BLOCKS = 16  # fewest blocks an error is read from (its relative uncertainty is then ~18 %)
STRESS = "M T-2"  # a 2D stress: force per length

# Series read from /observables (scalar ones by name; tensors reduced to a pressure).
SCALAR_OBSERVABLES = (
    "strain",
    "pressure",
    "shear_stress",
    "normal_stress_difference",
    "temperature",
    "solver_iterations",
    "solver_residual",
    "max_overlap",
)
PRESSURE_PARTS = {
    "pressure_kinetic": "stress_kinetic",
    "pressure_static": "stress_static",
    "pressure_collisional": "stress_collisional",
}
# Run columns: table name -> /parameters attribute of gf-shear (contract: CLI names + derived).
RUN_COLUMNS = {
    "packing_fraction": "packing_fraction",
    "restitution": "restitution",
    "tangential_restitution": "tangential-restitution",
    "friction": "friction",
    "rate": "rate",
    "strain_step": "strain-step",
    "strain": "strain",
    "dt": "dt",
    "grains": "grains",
    "seed": "seed",
    "mean_radius": "mean_radius",
    "mean_mass": "mean_mass",
}
# The unit string of each run column (the others are numbers, "1").
RUN_UNITS = {"rate": "T-1", "dt": "T", "mean_radius": "L", "mean_mass": "M"}


def _rate2_mass(p):
    return 1.0 / (p["rate"] ** 2 * p["mean_mass"])


# name -> (meaning, unit, constant factor c(parameters), {series: power}): Q = c * prod <x>^a.
QUANTITIES = {
    "pressure": ("p = (Σxx+Σyy)/2, total", STRESS, lambda p: 1.0, {"pressure": 1}),
    "shear_stress": ("s = -Σxy", STRESS, lambda p: 1.0, {"shear_stress": 1}),
    "temperature": ("T of eq. 4.5", "L+2 T-2", lambda p: 1.0, {"temperature": 1}),
    "pressure_kinetic": (
        "p^k: half trace of the kinetic stress (first term of eq. 4.6)",
        STRESS,
        lambda p: 1.0,
        {"pressure_kinetic": 1},
    ),
    "pressure_static": (
        "p^s: half trace of the static (contact) stress (second term of eq. 4.6)",
        STRESS,
        lambda p: 1.0,
        {"pressure_static": 1},
    ),
    "pressure_collisional": (
        "half trace of the collisional stress",
        STRESS,
        lambda p: 1.0,
        {"pressure_collisional": 1},
    ),
    "normal_stress_difference": (
        "N1 = <(Σxx-Σyy)/2> / <p>",
        "1",
        lambda p: 1.0,
        {"stress_half_difference": 1, "pressure": -1},
    ),
    "pressure_scaled": ("p/(γ̇² m), Fig 4.4 left", "1", _rate2_mass, {"pressure": 1}),
    "shear_stress_scaled": ("s/(γ̇² m), Fig 4.4 left", "1", _rate2_mass, {"shear_stress": 1}),
    "temperature_scaled": (
        "T/(γ̇² <R>²), Fig 4.4 right",
        "1",
        lambda p: 1.0 / (p["rate"] * p["mean_radius"]) ** 2,
        {"temperature": 1},
    ),
    "pressure_kinetic_scaled": ("p^k/(γ̇² m), Fig 4.5", "1", _rate2_mass, {"pressure_kinetic": 1}),
    "pressure_static_scaled": ("p^s/(γ̇² m), Figs 4.5, 4.6", "1", _rate2_mass, {"pressure_static": 1}),
    "pressure_collisional_scaled": ("collisional pressure/(γ̇² m)", "1", _rate2_mass, {"pressure_collisional": 1}),
    "s_over_p": ("s/p, Figs 4.3, 4.4 right", "1", lambda p: 1.0, {"shear_stress": 1, "pressure": -1}),
    "rate_R_over_sqrt_T": ("γ̇<R>/√T, Fig 4.3", "1", lambda p: p["rate"] * p["mean_radius"], {"temperature": -0.5}),
    "mT_over_pR2": (
        "m T/(p <R>²), Fig 4.3",
        "1",
        lambda p: p["mean_mass"] / p["mean_radius"] ** 2,
        {"temperature": 1, "pressure": -1},
    ),
}
DIAGNOSTICS = {
    "solver_iterations_mean": ("mean solver iterations per step", "1"),
    "solver_residual_max": ("largest solver residual (velocity × dt)", "L"),
    "max_overlap_max": ("largest overlap", "L"),
}


def read_run(path):
    """Parameters (the run columns) and recorded series of one gf-shear trajectory."""
    with h5py.File(path, "r") as f:
        attrs = f["/parameters"].attrs
        missing = [a for a in RUN_COLUMNS.values() if a not in attrs]
        if missing:
            raise ValueError(f"/parameters lacks {', '.join(missing)}")
        params = {col: (int if col in ("grains", "seed") else float)(attrs[a]) for col, a in RUN_COLUMNS.items()}
        obs = f["/observables"]
        series = {name: obs[name]["value"][...].astype(float) for name in SCALAR_OBSERVABLES}
        for name, tensor in PRESSURE_PARTS.items():
            v = obs[tensor]["value"][...]
            series[name] = 0.5 * (v[:, 0, 0] + v[:, 1, 1])
    lengths = {len(v) for v in series.values()}
    if len(lengths) != 1:
        raise ValueError(f"observables have different lengths {sorted(lengths)}")
    # N1 = (Σxx - Σyy)/2p per step, so N1·p recovers (Σxx - Σyy)/2 for a ratio of means.
    series["stress_half_difference"] = series["normal_stress_difference"] * series["pressure"]
    return {"parameters": params, "series": series}


def invariant_series(run):
    """Instantaneous s/p, γ̇<R>/√T and mT/(p<R>²) per step (Fig 4.3); NaN where T or p is 0."""
    s, p, t = (run["series"][k] for k in ("shear_stress", "pressure", "temperature"))
    prm = run["parameters"]
    with np.errstate(divide="ignore", invalid="ignore"):
        return {
            "s_over_p": np.where(p > 0, s / p, np.nan),
            "rate_R_over_sqrt_T": np.where(t > 0, prm["rate"] * prm["mean_radius"] / np.sqrt(t), np.nan),
            "mT_over_pR2": np.where(p > 0, prm["mean_mass"] * t / (p * prm["mean_radius"] ** 2), np.nan),
        }


def blocking_error(x):
    """(standard error of mean(x), blocks at the chosen level, plateau found) by
    Flyvbjerg-Petersen blocking with Jonsson's automatic choice of the level
    (lib/statistics/blocking.hpp)."""
    return statistics.blocking_error(x)


def estimate(series, parameters, factor, powers):
    """Q = factor * prod <x_k>^a_k over the given series and its blocking error."""
    c = factor(parameters)
    means = {k: float(np.mean(series[k])) for k in powers}
    q = c * math.prod(means[k] ** a for k, a in powers.items())
    # Linearisation: sum_k dQ/d<x_k> * x_k(t) (a constant shift leaves the error unchanged).
    lin = sum(
        c * a * means[k] ** (a - 1) * math.prod(means[j] ** b for j, b in powers.items() if j != k) * series[k]
        for k, a in powers.items()
    )
    err, _, plateau = blocking_error(lin)
    return q, err, plateau


def mser_truncation(x):
    """MSER: the d <= len(x)//2 minimising the variance of x[d:] over (len(x) - d)^2, the
    first on ties; 0 for fewer than 2 values (lib/statistics/steady.hpp)."""
    return statistics.mser_truncation(x)


def steady_start(run, from_strain, detect_transient=True):
    """Strain at which the steady part starts: from_strain, or with detect_transient the later
    of from_strain and MSER's truncation of the block means of T and of p (TRANSIENT_BLOCKS
    blocks of equal length over the run, the rows left over at the end not in any)."""
    if not detect_transient:
        return from_strain
    strain = run["series"]["strain"]
    row = statistics.mser_first_row([run["series"]["temperature"], run["series"]["pressure"]], TRANSIENT_BLOCKS)
    return max(from_strain, float(strain[min(row, len(strain) - 1)]))


def halves_change(x):
    """(mean of the second half of x - mean of the first, its error), each half's error by
    blocking (an odd count's middle value in neither half; lib/statistics/steady.hpp)."""
    return statistics.halves_change(x)


def halves_z(run, from_strain):
    """Largest |halves_change| of T and p over the rows at strain >= from_strain, in its
    errors (0 with too few rows to tell)."""
    keep = run["series"]["strain"] >= from_strain
    z = 0.0
    for name in ("temperature", "pressure"):
        x = run["series"][name][keep]
        if len(x) // 2 < MIN_SAMPLES:
            return 0.0
        change, error = halves_change(x)
        if error > 0:
            z = max(z, abs(change) / error)
    return z


def steady_values(run, from_strain, to_strain=math.inf):
    """({name: (value, error, plateau)} for every QUANTITIES entry, diagnostics, rows used)
    over the rows with from_strain <= strain < to_strain."""
    strain = run["series"]["strain"]
    keep = (strain >= from_strain) & (strain < to_strain)
    n = int(keep.sum())
    if n < MIN_SAMPLES:
        window = f"strain >= {from_strain}" + (f" and < {to_strain:g}" if to_strain < math.inf else "")
        raise ValueError(f"only {n} rows at {window} (need {MIN_SAMPLES}); run longer or lower --from-strain")
    steady = {k: v[keep] for k, v in run["series"].items()}
    bad = [k for k, v in steady.items() if not np.all(np.isfinite(v))]
    if bad:
        raise ValueError(f"non-finite values in the steady part of {', '.join(bad)}")
    values = {name: estimate(steady, run["parameters"], c, powers) for name, (_, _, c, powers) in QUANTITIES.items()}
    diagnostics = {
        "solver_iterations_mean": float(np.mean(steady["solver_iterations"])),
        "solver_residual_max": float(np.max(steady["solver_residual"])),
        "max_overlap_max": float(np.max(steady["max_overlap"])),
    }
    return values, diagnostics, n


def analyse(paths, from_strain, detect_transient=False):
    """One row per run: (path, sha256, parameters, steady values, diagnostics, samples,
    (steady_from, halves_z)); the steady part starts at steady_start() or, without
    detect_transient, at from_strain."""
    rows = []
    for path in paths:
        try:
            run = read_run(path)
            start = steady_start(run, from_strain, detect_transient)
            values, diagnostics, n = steady_values(run, start)
            z = halves_z(run, start)
        except (OSError, KeyError, ValueError, ZeroDivisionError) as exc:
            raise ValueError(f"{path}: {exc}") from exc
        rows.append((path, sha256(path), run["parameters"], values, diagnostics, n, (start, z)))
    return rows


def write_table(output, rows, from_strain, command_line, detect_transient=False):
    """Write the rows of analyse() as the table, atomically."""
    parameters = {"from_strain": from_strain, "detect_transient": int(detect_transient), "error_method": ERROR_METHOD}
    with outputs.table(output, os.path.abspath(__file__), command_line, parameters, [(r[0], r[1]) for r in rows]) as f:
        runs = f["runs"]
        for col, attr in RUN_COLUMNS.items():
            outputs.column(runs, col, [r[2][col] for r in rows], RUN_UNITS.get(col, "1"),
                           f"the run's /parameters attribute '{attr}'", dtype=None)
        outputs.column(runs, "samples", [r[5] for r in rows], "1", "observable rows averaged (strain >= steady_from)",
                       dtype=np.int64)
        outputs.column(runs, "steady_from", [r[6][0] for r in rows], "1",
                       f"strain the steady part starts at (>= {from_strain}; "
                       + ("MSER on T and p" if detect_transient else "fixed") + ")")
        outputs.column(runs, "halves_z", [r[6][1] for r in rows], "1",
                       "larger |difference| of the means of T and of p between the steady part's halves, in "
                       "combined blocking errors")
        outputs.column(runs, "stationary", [r[6][1] <= STATIONARY_SIGMAS for r in rows], "1",
                       f"1 if halves_z <= {STATIONARY_SIGMAS}", dtype=np.uint8)
        steady = f.create_group("steady")
        for name, (meaning, unit, _, _) in QUANTITIES.items():
            for suffix, col, what in (
                ("", 0, "steady-state value"),
                ("_error", 1, ERROR_METHOD),
                ("_plateau", 2, "1 if blocking reached a plateau, else the error is a lower bound"),
            ):
                outputs.column(steady, name + suffix, [r[3][name][col] for r in rows], unit if col < 2 else "1",
                               f"{meaning}: {what}", dtype=np.uint8 if col == 2 else float)
        diag = f.create_group("diagnostics")
        for name, (meaning, unit) in DIAGNOSTICS.items():
            outputs.column(diag, name, [r[4][name] for r in rows], unit, meaning + " over the steady part", dtype=None)


def read_table(path):
    """A steady-state table: {"runs": {column: array}, "steady": {name: array},
    "diagnostics": {name: array}, "parameters": {attribute: value}}."""
    return outputs.read_table(path, ("runs", "steady", "diagnostics"))


def select(table, **columns):
    """Indices of the rows whose run columns equal the given values, by increasing packing fraction."""
    keep = np.ones(len(table["runs"]["packing_fraction"]), dtype=bool)
    for col, value in columns.items():
        keep &= np.isclose(table["runs"][col], value, rtol=0, atol=1e-12)
    idx = np.flatnonzero(keep)
    return idx[np.argsort(table["runs"]["packing_fraction"][idx], kind="stable")]


def add_start_options(ap):
    """--from-strain and --detect-transient, the options of steady_start(), for every script
    that averages a run's steady part."""
    ap.add_argument("--from-strain", type=float, default=0.5, help="skip the transient before this strain (0.5)")
    ap.add_argument(
        "--detect-transient",
        action="store_true",
        help="start a run's steady part later than --from-strain where its own transient ends "
        "(MSER on block means of T and p)",
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_start_options(ap)
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("runs", nargs="+", help="gf-shear trajectories")
    args = ap.parse_args()
    try:
        rows = analyse(args.runs, args.from_strain, args.detect_transient)
    except ValueError as exc:  # bad input: exit 2, like the gf-* programs
        print(f"steady_state.py: {exc}", file=sys.stderr)
        sys.exit(2)
    write_table(args.output, rows, args.from_strain, shlex.join(sys.argv), args.detect_transient)


if __name__ == "__main__":
    main()
