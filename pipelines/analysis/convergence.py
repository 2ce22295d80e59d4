#!/usr/bin/env python3
"""convergence.py --default-step H --reference NU:E:MU --output OUT.h5 [--markdown OUT.md] [--classes-csv OUT.csv]
[--series-csv OUT.csv] TABLE.h5...:
every observable of the reproduction against the strain step h = γ̇dt, and its class.

Beside the tables' observables, from each run's own rows over the steady window: the mean of
the per-row ratio s/p and the relative spread of the per-row p (ROW_OBSERVABLES), to show what
the estimator does: per-step stresses are impulses over dt, their spread grows as dt shrinks,
and a mean of ratios is biased by it where the ratio of means (s_over_p) is not.

Inputs are per-run analysis tables of the convergence study (pipelines/convergence.mk): those of
steady_state.py, gf-correlate, gf-network, gf-kinetic and d2min_statistics.py, told apart by their /parameters
`program`. Each row is matched to its run by /runs/input; the run's own /parameters give N, ν, e,
μ, the tolerance and h = |γ̇|·dt. Rows of one (N, ν, e, μ, tolerance) form a series in h.

Classes, on the series of each point with the most steps at the default tolerance (OBSERVABLES
lists what is classified; errors are the tables' own: blocking, jackknife, delta method):
- converged: the value at the default step lies within max(σ, 1 %) of the value at the finest
  step, σ the two errors combined in quadrature, and σ is at most MAX_RELATIVE_ERROR of it;
- converging: Q(h) = Q0 + b·h^α fits (α profiled over ALPHA_GRID, weighted least squares in
  Q0, b; acceptable unless P(χ² >= χ²_fit) < MIN_FIT_PROBABILITY) and the interval of Q0 (Q0 ± its error over
  every α whose χ² is within max(1, χ²_min/dof) of the minimum) lies on the side of 0 of every
  value (a limit of the other sign is the quantity vanishing): the limit Q0, its
  error, and the step h_1% = (0.01·|Q0|/|b|)^(1/α) at which the fit is 1 % from it;
- regularisation-dependent: no limit of the values' sign is found, and over a factor of at
  least MIN_SPAN in h either Q = c·h^α fits (its exponent α and error) or Q moves monotonically
  by a factor of at least MIN_CHANGE (curved in log-log: the local exponent at the finest steps);
- unsettled: none of these (too few steps, a poor fit, or a limit of unknown sign).
A fit needs at least MIN_STEPS steps, a limit one more. The bounds of ALPHA_GRID are a prior: a quantity that
moves as a smaller power of h, or as log h, is not told from one that converges.

Output (HDF5, written atomically): /parameters (program, script_sha256, command_line,
default_step, reference, activation (the runs' gf-shear --activation: runs of two activations are
refused), thresholds); /runs/input, input_sha256 (the tables read);
/series/<column> [rows], one row per (point, N, tolerance, observable, step): grains,
packing_fraction, restitution, friction, tolerance, step, observable, unit, value, error;
/classes/<column> [rows], one row per (point, observable) classified: packing_fraction,
restitution, friction, grains, observable, unit, class, steps, span, default_value, default_error,
finest_step, finest_value, finest_error, limit, limit_error, limit_exponent, step_1pct,
exponent, exponent_error, chi2_dof, exponent_finest (between the two finest steps), change
(finest over coarsest value), power_fits (1 when c·h^α fits). --markdown writes the same as tables, one per point;
Values, errors and limits are in the row's unit (the string column `unit`, the observable's unit in its
table divided by γ̇^power; their datasets' attribute unit_column = "unit"); the other columns are numbers.
--classes-csv the classes alone, one CSV line per (point, observable), for the report (pipelines/report) --step-classes;
--series-csv every value of /series, one CSV line per (point, N, tolerance, step, observable), with its label and unit.
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
from granflow import units as granflow_units
from granflow.hdf5 import read_attrs, read_dataset, sha256, text

# (key, label, program, dataset, error dataset or None, power of γ̇ it is divided by)
OBSERVABLES = (
    ("p", "p/(mγ̇²)", "steady_state.py", "steady/pressure_scaled", "steady/pressure_scaled_error", 0),
    ("s_over_p", "s/p", "steady_state.py", "steady/s_over_p", "steady/s_over_p_error", 0),
    ("T", "T/(γ̇²⟨R⟩²)", "steady_state.py", "steady/temperature_scaled", "steady/temperature_scaled_error", 0),
    ("p_s", "p^s/(mγ̇²)", "steady_state.py", "steady/pressure_static_scaled", "steady/pressure_static_scaled_error", 0),
    ("p_k", "p^k/(mγ̇²)", "steady_state.py", "steady/pressure_kinetic_scaled", "steady/pressure_kinetic_scaled_error", 0),
    ("p_bc", "p^bc/(mγ̇²)", "steady_state.py", "steady/pressure_collisional_scaled",
     "steady/pressure_collisional_scaled_error", 0),
    ("xi", "ξ (eq. 5.2)", "gf-correlate", "correlation/xi", "correlation/xi_error", 0),
    ("xi_abs", "ξ_|C|", "gf-correlate", "correlation/xi_abs", "correlation/xi_abs_error", 0),
    ("xi_ratio", "ξ/ξ_el", "gf-correlate", "correlation/xi_ratio", "correlation/xi_ratio_error", 0),
    ("xi_abs_ratio", "ξ_|C|/ξ_el,|C|", "gf-correlate", "correlation/xi_abs_ratio", "correlation/xi_abs_ratio_error", 0),
    ("xi_length_ratio", "ξ/ξ_el, C per unit length", "gf-correlate", "correlation/xi_length_ratio",
     "correlation/xi_length_ratio_error", 0),
    ("a0", "a0 (eq. 5.3)", "gf-correlate", "correlation/a0", "correlation/a0_error", 0),
    ("theta0", "θ0 (eq. 5.3)", "gf-correlate", "correlation/theta0", "correlation/theta0_error", 0),
    ("a0_direction", "a0, eq. 5.2 per direction", "gf-correlate", "correlation/a0_direction",
     "correlation/a0_direction_error", 0),
    ("theta0_direction", "θ0, eq. 5.2 per direction", "gf-correlate", "correlation/theta0_direction",
     "correlation/theta0_direction_error", 0),
    ("pf_mode", "P(f)'s mode", "gf-correlate", "forces/mode", "forces/mode_error", 0),
    ("pf_zero", "P(0)/P_max", "gf-correlate", "forces/p0_over_pmax", None, 0),
    ("z", "z (age ≥ 2)", "gf-network", "runs/coordination", "runs/coordination_error", 0),
    ("Phi", "Φ", "gf-network", "runs/Phi", "runs/Phi_error", 0),
    ("Psi", "Ψ", "gf-network", "runs/Psi", "runs/Psi_error", 0),
    ("a_c", "a_c", "gf-network", "runs/a_c", "runs/a_c_error", 0),
    ("a_c_prime", "a′_c", "gf-network", "runs/a_c_prime", "runs/a_c_prime_error", 0),
    ("a4_c", "4θ of C(θ)", "gf-network", "runs/a4_c", "runs/a4_c_error", 0),
    ("lhs_627", "(p^s − p^bc)/p^bc", "gf-network", "prediction/lhs_pressure", "prediction/lhs_pressure_error", 0),
    ("rhs_627", "eq. 6.27's rhs", "gf-network", "prediction/rhs_pressure", "prediction/rhs_pressure_error", 0),
    ("C_v", "C_v (eq. 6.11)", "gf-kinetic", "runs/velocity_correlation", "runs/velocity_correlation_error", 0),
    ("omega", "collisions/(grain γ̇)", "gf-kinetic", "runs/collision_frequency", "runs/collision_frequency_error", 1),
    ("d2min_black", "D²min: black fraction", "d2min_statistics.py", "runs/black_fraction", "runs/black_fraction_error", 0),
    ("d2min_median", "D²min: median/⟨d⟩²", "d2min_statistics.py", "runs/d2min_median", "runs/d2min_median_error", 0),
    ("d2min_largest", "D²min: largest cluster", "d2min_statistics.py", "runs/largest_cluster",
     "runs/largest_cluster_error", 0),
    ("d2min_jaccard", "D²min: J(a, b)", "d2min_statistics.py", "runs/jaccard", "runs/jaccard_error", 0),
)
# From the run's own rows over the steady table's window (steady_from): the mean of the per-row
# ratio s/p, an estimator every table avoids (a ratio of means is what they report), kept to
# show how it is biased by the per-step stress fluctuations, and those fluctuations.
ROW_OBSERVABLES = (
    ("s_over_p_rows", "⟨s/p⟩ per row (biased)", "steady_state.py"),
    ("p_cv", "std(p)/⟨p⟩ per row", "steady_state.py"),
)
# Of a gf-network table made with --contact-gap H (geometric contacts): these, as "<key>@H".
GEOMETRIC_KEYS = ("z", "Phi", "Psi", "a_c")
# On the reference point: ξ_el itself.
REFERENCE_OBSERVABLES = (("xi_el", "ξ_el", "gf-correlate", "correlation/xi_el", "correlation/xi_el_error", 0),)
REFERENCE_KEYS = {o[0] for o in REFERENCE_OBSERVABLES}

ALPHA_GRID = np.linspace(0.25, 2.0, 71)
# A fit is acceptable unless its χ² is this improbable.
MIN_FIT_PROBABILITY = 1e-3
MIN_STEPS = 3
MIN_SPAN = 16.0
# A series that moves monotonically by at least this factor over MIN_SPAN, with no limit of its
# sign, is regularisation-dependent even where one power does not fit it.
MIN_CHANGE = 2.0
RELATIVE_TOLERANCE = 0.01
MAX_RELATIVE_ERROR = 0.1
STEP_KEY_DIGITS = 12


def point_text(nu, e, mu):
    return f"{nu:.3f}:{e:.2f}:{mu:.2f}"


def parse_point(text):
    parts = text.split(":")
    if len(parts) != 3:
        raise ValueError(f"a point is ν:e:μ (got '{text}')")
    return tuple(float(p) for p in parts)


# ------------------------------------------------------------------ fits and classes
def chi2_probability(chi2, dof):
    """P(χ²_dof >= chi2): the probability of a χ² at least this large (integer dof >= 1)."""
    half = chi2 / 2.0
    if dof % 2 == 0:
        term, total = 1.0, 1.0
        for i in range(1, dof // 2):
            term *= half / i
            total += term
        return math.exp(-half) * total
    total = math.erfc(math.sqrt(half))
    term = math.sqrt(half / math.pi) * math.exp(-half) * 2.0
    for i in range(1, (dof + 1) // 2):
        total += term
        term *= half / (i + 0.5)
    return total


def acceptable(fit):
    """A fit without spare degrees of freedom, or whose χ² is not improbably large."""
    return fit["dof"] == 0 or chi2_probability(fit["chi2"], fit["dof"]) >= MIN_FIT_PROBABILITY


def fit_limit(h, q, sigma, alphas=ALPHA_GRID):
    """Q = Q0 + b h^α by weighted least squares, α profiled over `alphas`. Returns a dict with
    q0, q0_error (over the α within Δχ² = max(1, χ²_min/dof) of the minimum), b, alpha, chi2, dof,
    or None when there are fewer than 3 points."""
    h, q, sigma = (np.asarray(v, dtype=float) for v in (h, q, sigma))
    if len(h) < 3:
        return None
    w = 1.0 / sigma**2
    fits = []
    for alpha in alphas:
        # In units of the largest step, so that the two columns are of one size.
        x = (h / h.max()) ** alpha
        a = np.column_stack([np.ones_like(x), x]) * np.sqrt(w)[:, None]
        cov = np.linalg.pinv(a.T @ a)
        beta = cov @ (a.T @ (q * np.sqrt(w)))
        chi2 = float(np.sum(w * (q - beta[0] - beta[1] * x) ** 2))
        if math.isfinite(chi2) and cov[0, 0] > 0:
            fits.append((chi2, alpha, beta[0], beta[1] / h.max() ** alpha, math.sqrt(cov[0, 0])))
    if not fits:
        return None
    dof = len(h) - 3
    best = min(fits)
    delta = max(1.0, best[0] / dof) if dof > 0 else 1.0
    inside = [f for f in fits if f[0] <= best[0] + delta]
    low = min(f[2] - f[4] for f in inside)
    high = max(f[2] + f[4] for f in inside)
    # Without a spare degree of freedom the scatter cannot widen the error: keep the conditional one.
    return {
        "q0": best[2],
        "q0_error": max(best[2] - low, high - best[2]),
        "q0_low": low,
        "q0_high": high,
        "b": best[3],
        "alpha": best[1],
        "chi2": best[0],
        "dof": dof,
    }


def fit_power(h, q, sigma):
    """Q = c h^α, weighted least squares in ln Q (σ/|Q|): alpha, alpha_error, chi2, dof, or None
    when a value is not of one sign or there are fewer than 3 points."""
    h, q, sigma = (np.asarray(v, dtype=float) for v in (h, q, sigma))
    if len(h) < 3 or not (np.all(q > 0) or np.all(q < 0)):
        return None
    y = np.log(np.abs(q))
    s = sigma / np.abs(q)
    w = 1.0 / s**2
    x = np.log(h / h.max())
    a = np.column_stack([np.ones_like(h), x]) * np.sqrt(w)[:, None]
    cov = np.linalg.pinv(a.T @ a)
    beta = cov @ (a.T @ (y * np.sqrt(w)))
    chi2 = float(np.sum(w * (y - beta[0] - beta[1] * x) ** 2))
    if not (math.isfinite(chi2) and cov[1, 1] > 0):
        return None
    dof = len(h) - 2
    scale = max(1.0, chi2 / dof) if dof > 0 else 1.0
    return {"alpha": beta[1], "alpha_error": math.sqrt(cov[1, 1] * scale), "chi2": chi2, "dof": dof}


def monotonic(q, sigma):
    """Every step between neighbours in one direction by more than their combined error."""
    d = np.diff(q)
    e = np.sqrt(np.nan_to_num(sigma[1:]) ** 2 + np.nan_to_num(sigma[:-1]) ** 2)
    return bool(np.all(d > e) or np.all(d < -e))


def classify(steps, values, errors, default_step):
    """The class of one series (steps, values, errors: arrays over h) with its numbers; errors
    that are missing (NaN) count as 0 against the 1 % rule and take 1 % of |Q| in the fits."""
    order = np.argsort(steps)[::-1]
    h = np.asarray(steps, dtype=float)[order]
    q = np.asarray(values, dtype=float)[order]
    s = np.asarray(errors, dtype=float)[order]
    ok = np.isfinite(q)
    h, q, s = h[ok], q[ok], s[ok]
    result = {
        "class": "unsettled",
        "steps": len(h),
        "span": float(h[0] / h[-1]) if len(h) else math.nan,
        "default_value": math.nan,
        "default_error": math.nan,
        "finest_step": float(h[-1]) if len(h) else math.nan,
        "finest_value": float(q[-1]) if len(h) else math.nan,
        "finest_error": float(s[-1]) if len(h) else math.nan,
        "limit": math.nan,
        "limit_error": math.nan,
        "limit_exponent": math.nan,
        "step_1pct": math.nan,
        "exponent": math.nan,
        "exponent_error": math.nan,
        "chi2_dof": math.nan,
        "exponent_finest": math.nan,
        "change": math.nan,
        "power_fits": 0.0,
    }
    if len(h) < 2:
        return result
    at_default = np.flatnonzero(np.isclose(h, default_step, rtol=1e-9, atol=0))
    if len(at_default):
        k = at_default[0]
        result["default_value"], result["default_error"] = float(q[k]), float(s[k])
        if k != len(h) - 1:
            sigma = math.sqrt(np.nan_to_num(s[k]) ** 2 + np.nan_to_num(s[-1]) ** 2)
            # Errors larger than MAX_RELATIVE_ERROR of the value cannot show convergence.
            precise = sigma <= MAX_RELATIVE_ERROR * abs(q[-1])
            if precise and abs(q[k] - q[-1]) <= max(sigma, RELATIVE_TOLERANCE * abs(q[-1])):
                result["class"] = "converged"
    # A value without an error weighs as one known to 1 % of the series' largest |Q|.
    floor = RELATIVE_TOLERANCE * float(np.max(np.abs(q)))
    fit_sigma = np.where(np.isfinite(s) & (s > 0), s, floor)
    if len(h) >= MIN_STEPS and floor > 0:
        limit = fit_limit(h, q, fit_sigma)
        if limit is not None and acceptable(limit):
            result["limit"], result["limit_error"] = limit["q0"], limit["q0_error"]
            result["limit_exponent"] = limit["alpha"]
            result["chi2_dof"] = limit["chi2"] / limit["dof"] if limit["dof"] else math.nan
            if limit["b"] != 0 and limit["q0"] != 0:
                result["step_1pct"] = (RELATIVE_TOLERANCE * abs(limit["q0"]) / abs(limit["b"])) ** (1.0 / limit["alpha"])
            # A limit needs a spare degree of freedom: three steps always fit three parameters.
            # A limit of the other sign than every value is the quantity vanishing, not converging.
            same_sign = (limit["q0_low"] > 0 and np.all(q > 0)) or (limit["q0_high"] < 0 and np.all(q < 0))
            has_limit = limit["dof"] >= 1 and same_sign
        else:
            has_limit = False
        power = fit_power(h, q, fit_sigma)
        if power is not None:
            result["exponent"], result["exponent_error"] = power["alpha"], power["alpha_error"]
            result["power_fits"] = float(acceptable(power))
        if np.all(q > 0) or np.all(q < 0):
            result["exponent_finest"] = math.log(q[-1] / q[-2]) / math.log(h[-1] / h[-2])
            result["change"] = float(q[-1] / q[0])
        wide = result["span"] >= MIN_SPAN * (1 - 1e-9)
        if result["class"] != "converged":
            if has_limit:
                result["class"] = "converging"
            elif (
                power is not None
                and wide
                and acceptable(power)
                and abs(power["alpha"]) > 2 * power["alpha_error"]
            ):
                result["class"] = "regularisation-dependent"
            elif wide and monotonic(q, s) and max(result["change"], 1 / result["change"]) >= MIN_CHANGE:
                # Curved in log-log, but moving by a factor over the span with no limit in sight.
                result["class"] = "regularisation-dependent"
    return result


# ------------------------------------------------------------------ reading
def run_key(run_path, cache):
    """(grains, ν, e, μ, tolerance, step) of a gf-shear run, from its /parameters."""
    if run_path not in cache:
        with h5py.File(run_path, "r") as f:
            a = read_attrs(f["parameters"])
        step = abs(float(a["rate"])) * float(a["dt"])
        cache[run_path] = (
            int(a["grains"]),
            round(float(a["packing_fraction"]), 6),
            round(float(a["restitution"]), 6),
            round(float(a["friction"]), 6),
            float(a["tolerance"]),
            float(f"{step:.{STEP_KEY_DIGITS}g}"),
            abs(float(a["rate"])),
        )
    return cache[run_path]


def run_activation(run_path):
    """gf-shear's --activation of a run (predicted-gap for runs made before the option)."""
    with h5py.File(run_path, "r") as f:
        return str(read_attrs(f["parameters"]).get("activation", "predicted-gap"))


def geometric_observables(gap):
    """The GEOMETRIC_KEYS of a gf-network table over geometric contacts within `gap` mean diameters."""
    return tuple(
        (f"{key}@{gap:g}", f"{label}, gap {gap:g}σ", prog, name, error, power)
        for key, label, prog, name, error, power in OBSERVABLES
        if key in GEOMETRIC_KEYS
    )


def all_observables(rows):
    """Every observable of the tables, in OBSERVABLES order, the geometric ones after their force-bearing
    counterpart (by increasing gap)."""
    present = {obs for entry in rows.values() for obs in entry}
    gaps = sorted({float(o.split("@")[1]) for o in present if "@" in o})
    result = []
    for item in OBSERVABLES + REFERENCE_OBSERVABLES:
        result.append(item)
        if item[0] == "s_over_p":
            result.extend((key, label, prog, None, None, 0) for key, label, prog in ROW_OBSERVABLES)
        if item[0] in GEOMETRIC_KEYS:
            result.extend(o for g in gaps for o in geometric_observables(g) if o[0] == f"{item[0]}@{g:g}")
    return result


def row_statistics(run_path, from_strain):
    """(⟨s/p⟩ over the rows at |strain| >= from_strain with its blocking error, std(p)/⟨p⟩) of a
    gf-shear run, from its /observables pressure and shear_stress."""
    from granflow import statistics

    def series(f, name):
        g = f["observables"][name]
        return np.asarray(g["value"][()] if isinstance(g, h5py.Group) else g[()], dtype=float)

    with h5py.File(run_path, "r") as f:
        keep = np.abs(series(f, "strain")) >= from_strain
        p = series(f, "pressure")[keep]
        ratio = series(f, "shear_stress")[keep] / p
    try:
        error = statistics.blocking_error(ratio)[0]
    except ValueError:
        error = math.nan
    return (float(np.mean(ratio)), error), (float(np.std(p) / np.mean(p)), math.nan)


def read_rows(paths):
    """({(grains, ν, e, μ, tol, step): {observable key: (value, error)}} over every table, the
    runs' contact activation, {observable key: unit string}, the unit of its value as divided by
    γ̇^power); ValueError when the runs mix activations, or a table gives an observable no unit
    or another unit than the others."""
    cache = {}
    rows = {}
    activations = {}
    units = {key: "1" for key, _, _ in ROW_OBSERVABLES}
    for path in paths:
        with h5py.File(path, "r") as f:
            parameters = read_attrs(f["parameters"])
            program = parameters.get("program", "")
            gap = parameters.get("contact-gap")
            observables = OBSERVABLES + REFERENCE_OBSERVABLES
            if gap is not None:
                observables = geometric_observables(float(gap))
            inputs = read_dataset(f["runs/input"])
            base = os.path.dirname(os.path.abspath(path))
            for i, run in enumerate(inputs):
                run_path = run if os.path.isabs(run) or os.path.exists(run) else os.path.join(base, run)
                *key, rate = run_key(run_path, cache)
                if run_path not in activations:
                    activations[run_path] = run_activation(run_path)
                entry = rows.setdefault(tuple(key), {})
                if program == "steady_state.py":
                    mean_ratio, cv = row_statistics(run_path, float(f["runs/steady_from"][i]))
                    entry["s_over_p_rows"], entry["p_cv"] = mean_ratio, cv
                for obs, _label, prog, name, error, power in observables:
                    if prog != program or name not in f:
                        continue
                    if "unit" not in f[name].attrs:
                        raise ValueError(f"{path}: {name} has no unit attribute (a table made before units: remake it)")
                    unit = granflow_units.times_power(text(f[name].attrs["unit"]), "T", power)
                    if units.setdefault(obs, unit) != unit:
                        raise ValueError(f"{path}: {name} is in {unit}, other tables give {obs} in {units[obs]}")
                    if np.atleast_1d(f[name][()]).shape[0] != len(inputs):
                        raise ValueError(f"{path}: {name} has not one row per input run ({len(inputs)})")
                    value = float(np.atleast_1d(f[name][()])[i]) / rate**power
                    err = float(np.atleast_1d(f[error][()])[i]) / rate**power if error and error in f else math.nan
                    entry[obs] = (value, err)
    kinds = sorted(set(activations.values()))
    if len(kinds) > 1:
        example = {k: next(p for p, a in activations.items() if a == k) for k in kinds}
        raise ValueError(
            "the runs mix contact activations (" + ", ".join(f"{k}: {example[k]}" for k in kinds) + "); "
            "study one per convergence.py call"
        )
    return rows, (kinds[0] if kinds else "predicted-gap"), units


# ------------------------------------------------------------------ output
def fmt(value, error=math.nan):
    if not np.isfinite(value):
        return "—"
    if not np.isfinite(error) or error <= 1e-12 * abs(value):
        return f"{value:.4g}"
    digits = max(0, 1 - int(math.floor(math.log10(error)))) if error > 0 else 3
    digits = min(digits, 8)
    if abs(value) >= 1e4 or (abs(value) < 1e-3 and value != 0):
        return f"{value:.3e} ± {error:.1e}"
    return f"{value:.{digits}f} ± {error:.{digits}f}"


def class_text(c):
    if c["class"] == "converging":
        text = f"converging: limit {fmt(c['limit'], c['limit_error'])} (α = {c['limit_exponent']:.2f})"
        if np.isfinite(c["step_1pct"]):
            text += f", 1 % at γ̇dt ≈ {c['step_1pct']:.1e}"
        return text
    if c["class"] == "regularisation-dependent":
        if c["power_fits"] == 1 and np.isfinite(c["exponent_error"]):
            text = f"regularisation-dependent: ∝ (γ̇dt)^{c['exponent']:.2f}±{c['exponent_error']:.2f}"
        else:
            text = "regularisation-dependent"
        return text + f"; ×{c['change']:.2g} over the span, local exponent {c['exponent_finest']:.2f} at the finest steps"
    if c["class"] == "converged":
        return "converged"
    if c["steps"] < MIN_STEPS:
        return "unsettled (too few steps)"
    return "unsettled"


def markdown(series, classes, default_step, tolerance, observables, activation="predicted-gap"):
    lines = []
    points = sorted({(k[1], k[2], k[3], k[0]) for k in series})
    for nu, e, mu, grains in points:
        keys = sorted(
            [k for k in series if k[:4] == (grains, nu, e, mu)], key=lambda k: (not math.isclose(k[4], tolerance, rel_tol=1e-9), k[4])
        )
        for key in keys:
            steps = sorted(series[key], reverse=True)
            tol = key[4]
            lines.append(
                f"### ν = {nu:.3f}, e = {e:.2f}, μ = {mu:.2f}, N = {grains}, tolerance {tol:g}"
                + ("" if activation == "predicted-gap" else f", activation {activation}")
            )
            lines.append("")
            head = ["observable"] + [
                f"γ̇dt = {h:g}" + (" (default)" if math.isclose(h, default_step, rel_tol=1e-9) else "") for h in steps
            ]
            cls = classes.get(key)
            if cls is not None:
                head.append("class")
            lines.append("| " + " | ".join(head) + " |")
            lines.append("|" + "---|" * len(head))
            labels = {o[0]: o[1] for o in observables}
            for obs in [o[0] for o in observables]:
                cells = [series[key][h].get(obs) for h in steps]
                if all(c is None for c in cells):
                    continue
                row = [labels[obs]] + [fmt(*c) if c is not None else "—" for c in cells]
                if cls is not None:
                    row.append(class_text(cls[obs]) if obs in cls else "")
                lines.append("| " + " | ".join(row) + " |")
            lines.append("")
    return "\n".join(lines) + "\n"



def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--default-step", type=float, required=True, help="the reproduction's γ̇dt (1e-3)")
    ap.add_argument("--reference", required=True, help="the reference point ν:e:μ (ξ_el)")
    ap.add_argument("--tolerance", type=float, default=1e-10, help="the default solver tolerance (1e-10)")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--markdown", help="also write the tables as Markdown to this file")
    ap.add_argument("--classes-csv", help="also write every class as one CSV line per point and observable here")
    ap.add_argument("--series-csv", help="also write every value as one CSV line per point, N, tolerance, step and "
                                         "observable here")
    ap.add_argument("tables", nargs="+", help="per-run tables of steady_state.py, gf-correlate, gf-network, gf-kinetic")
    args = ap.parse_args()
    try:
        reference = parse_point(args.reference)
    except ValueError as err:
        ap.error(f"--reference: {err}")
    if not args.default_step > 0:
        ap.error("--default-step must be positive")
    for path in args.tables:
        if not os.path.isfile(path):
            ap.error(f"{path}: no such table")
    for out in (args.output, args.markdown, args.classes_csv, args.series_csv):
        if out and any(os.path.abspath(out) == os.path.abspath(t) for t in args.tables):
            ap.error(f"{out}: the output is also an input")
    try:
        rows, activation, units = read_rows(args.tables)
    except (OSError, KeyError, ValueError) as err:
        print(f"convergence.py: {err}", file=sys.stderr)
        return 2

    observables = all_observables(rows)
    # series[(grains, ν, e, μ, tol)][step] = {observable: (value, error)}
    series = {}
    for (grains, nu, e, mu, tol, step), obs in rows.items():
        series.setdefault((grains, nu, e, mu, tol), {})[step] = obs
    # Classes per point on the default tolerance's series with the most steps.
    classes = {}
    for (nu, e, mu) in {(k[1], k[2], k[3]) for k in series}:
        grains_list = sorted(
            k[0] for k in series if k[1:4] == (nu, e, mu) and math.isclose(k[4], args.tolerance, rel_tol=1e-9)
        )
        # The N with the most steps (the step series); larger cells come at a few steps only.
        best = max(
            grains_list,
            key=lambda g: (len(series[(g, nu, e, mu, args.tolerance)]), -g),
            default=None,
        )
        if best is None:
            continue
        key = (best, nu, e, mu, args.tolerance)
        per_obs = {}
        for obs, *_ in observables:
            if obs in REFERENCE_KEYS and (nu, e, mu) != reference:
                continue
            steps = [h for h in series[key] if obs in series[key][h]]
            if not steps:
                continue
            per_obs[obs] = classify(
                steps, [series[key][h][obs][0] for h in steps], [series[key][h][obs][1] for h in steps],
                args.default_step,
            )
        classes[key] = per_obs

    inputs = [(p, sha256(p)) for p in args.tables]
    command_line = " ".join(shlex.quote(a) for a in sys.argv)
    params = {
        "default_step": args.default_step,
        "reference": args.reference,
        "tolerance": args.tolerance,
        "activation": activation,
        "relative_tolerance": RELATIVE_TOLERANCE,
        "max_relative_error": MAX_RELATIVE_ERROR,
        "min_fit_probability": MIN_FIT_PROBABILITY,
        "min_steps": MIN_STEPS,
        "min_span": MIN_SPAN,
        "alpha_min": float(ALPHA_GRID[0]),
        "alpha_max": float(ALPHA_GRID[-1]),
    }
    with outputs.table(args.output, __file__, command_line, params, inputs) as f:
        cols = {k: [] for k in ("grains", "packing_fraction", "restitution", "friction", "tolerance", "step",
                                "observable", "unit", "value", "error")}
        for key in sorted(series):
            for step in sorted(series[key], reverse=True):
                for obs, (value, error) in series[key][step].items():
                    for name, v in zip(cols, (*key, step, obs, units[obs], value, error)):
                        cols[name].append(v)
        # Values, errors and limits are in each row's unit (its observable's); the rest are numbers.
        in_row_unit = ("value", "error", "default_value", "default_error", "finest_value", "finest_error", "limit",
                       "limit_error")
        outputs.column_group(f, "series", cols, {c: "unit" if c in in_row_unit else "1" for c in cols},
                             integers=("grains",))
        ccols = {}
        for key in sorted(classes):
            for obs, c in classes[key].items():
                entry = {"grains": key[0], "packing_fraction": key[1], "restitution": key[2], "friction": key[3],
                         "observable": obs, "unit": units[obs], **c}
                for name, v in entry.items():
                    ccols.setdefault(name, []).append(v)
        outputs.column_group(f, "classes", ccols, {c: "unit" if c in in_row_unit else "1" for c in ccols},
                             integers=("grains", "steps"))
    if args.markdown:
        outputs.write_text(args.markdown, markdown(series, classes, args.default_step, args.tolerance, observables,
                                                   activation))
    if args.classes_csv:
        write_classes_csv(args.classes_csv, classes, observables, args.default_step, activation)
    if args.series_csv:
        write_series_csv(args.series_csv, series, observables, units, args.default_step, activation)
    return 0


CSV_COLUMNS = ("packing_fraction", "restitution", "friction", "grains", "observable", "label", "class",
               "default_value", "default_error", "limit", "limit_error", "exponent", "exponent_error")
SERIES_CSV_COLUMNS = ("packing_fraction", "restitution", "friction", "grains", "tolerance", "step", "observable",
                      "label", "unit", "value", "error")


def write_csv(path, what, columns, rows, default_step, activation):
    """The study's CSV files: a comment line naming what they hold, the default step and the
    activation (the report and python.test_convergence read it), the header, then the rows."""
    fh = io.StringIO()
    fh.write(f"# convergence.py {what} at the default step {default_step:g}, activation {activation}\n")
    w = csv.writer(fh, lineterminator="\n")
    w.writerow(columns)
    w.writerows(rows)
    outputs.write_text(path, fh.getvalue())


def point_cells(grains, nu, e, mu):
    """A point's cells as both CSV files write them: ν, e, μ, N."""
    return [f"{nu:.3f}", f"{e:.2f}", f"{mu:.2f}", grains]


def write_classes_csv(path, classes, observables, default_step, activation):
    """One line per (point, observable) classified: the columns of CSV_COLUMNS (read by the report,
    pipelines/report, --step-classes)."""
    labels = {o[0]: o[1] for o in observables}
    rows = ([*point_cells(*key[:4]), obs, labels.get(obs, obs), c["class"], *(f"{c[k]:.6g}" for k in CSV_COLUMNS[7:])]
            for key in sorted(classes) for obs, c in sorted(classes[key].items()))
    write_csv(path, "classes", CSV_COLUMNS, rows, default_step, activation)


def write_series_csv(path, series, observables, units, default_step, activation):
    """One line per (point, N, tolerance, step, observable): the columns of SERIES_CSV_COLUMNS (value and
    error in the row's unit, empty when not finite); points in order, steps from the coarsest,
    observables in the tables' order."""
    labels = {o[0]: o[1] for o in observables}

    def number(x):
        return f"{x:.6g}" if np.isfinite(x) else ""

    def rows():
        for key in sorted(series, key=lambda k: (k[1], k[2], k[3], k[0], k[4])):
            for step in sorted(series[key], reverse=True):
                values = series[key][step]
                for obs in (o[0] for o in observables if o[0] in values):
                    value, error = values[obs]
                    yield [*point_cells(*key[:4]), f"{key[4]:g}", f"{step:g}", obs, labels[obs], units[obs],
                           number(value), number(error)]

    write_csv(path, "series", SERIES_CSV_COLUMNS, rows(), default_step, activation)

if __name__ == "__main__":
    sys.exit(main())
