#!/usr/bin/env python3
"""jamming_point.py [--friction MU] [--restitution E] [--from-nu NU] [--exponent B ...] --output
FIT.h5 TABLE.h5...: the packing fraction ν_c at which the steady stresses of simple shear diverge
(the jamming point of thesis §5.2, where ξ diverges: ν_c(μ) "depends on the friction coefficient μ,
but not on the restitution coefficient e"; ν_c ≈ 0.845 for μ = 0, Fig 5.10), from steady_state.py
tables of gf-shear runs.

For perfectly rigid grains p/(mγ̇²) and s/(mγ̇²) are functions of ν alone (Bagnold), and near ν_c
they grow as A (ν_c − ν)^(−β). Per (μ, e) group of rows with ν >= --from-nu and per quantity
(pressure_scaled and shear_stress_scaled of the table), the fit minimises
    χ² = Σ [(ln q_i − ln A + β ln(ν_c − ν_i)) / (σ_i / q_i)]²
over A, β and ν_c > max ν_i (weighted least squares in ln q, with the tables' blocking errors σ_i),
as every reading: β free, and β fixed at each --exponent (default 2; the exponent is not settled
in the literature, so the fixed readings show how far ν_c depends on it). For a given ν_c the
minimum over (ln A, β) is linear, so ν_c is found by profiling χ² over the distance
d = ν_c − max ν_i on a logarithmic grid (10⁻⁶ to --max-distance) and refining the minimum by
golden section. Its interval is where the profile stays within Δχ² = max(1, χ²_min/dof) of the
minimum (Δχ² = 1, widened by the reduced χ² when the points scatter more than their errors:
packings differ by more than a run's blocking error says). An end that the profile never
leaves within that Δχ² is reported as unbounded (nu_c_high = inf: the data do not show where
the divergence is; nu_c_low = max ν_i: it could be just above the densest point). A minimum
at the largest distance (no divergence seen) gives nu_c = inf.

A group with fewer than 4 runs at ν >= --from-nu is not fitted; it is listed under /skipped
(the table may then hold no fit at all, as for a grid that stops far below ν_c).

Several tables may be given (e.g. the chapter-4 and chapter-5 sweeps): rows of one run that
appear twice (same input path) are counted once; different packings at the same ν all count.

Output (HDF5, atomically): /parameters (program, script_sha256, command_line, from_nu,
max_distance, exponents); /runs/input, input_sha256 (the tables read); /fits/<column> [rows],
one row per (friction, restitution, quantity, reading): friction, restitution, quantity (text),
exponent_fixed (NaN when β is free), points, nu_max, nu_c, nu_c_low, nu_c_high, exponent,
amplitude, chi2, dof; /skipped/friction, restitution, points: the groups not fitted.
"""
import argparse
import math
import os
import shlex
import sys

import numpy as np

from analysis import steady_state
from granflow import outputs
from granflow.hdf5 import sha256

QUANTITIES = ("pressure_scaled", "shear_stress_scaled")
GRID_POINTS = 2000
# The free-β fit has 3 parameters; one point more leaves a χ² to judge it by.
MIN_POINTS = 4
MIN_DISTANCE = 1e-6
GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0

MEANINGS = {
    "friction": "μ of the group's runs",
    "restitution": "e of the group's runs",
    "quantity": "the steady_state.py column fitted (q = A (ν_c − ν)^−β)",
    "exponent_fixed": "β held fixed in this reading; NaN when β is fitted",
    "points": "runs in the fit (ν >= from_nu)",
    "nu_max": "densest ν in the fit",
    "nu_c": "best ν_c (inf when the fit sees no divergence)",
    "nu_c_low": "lower end of ν_c's interval (Δχ² = max(1, χ²/dof)); nu_max when unbounded below",
    "nu_c_high": "upper end of ν_c's interval; inf when unbounded",
    "exponent": "β (fitted, or the fixed value)",
    "amplitude": "A, in the units of the quantity",
    "chi2": "χ² at the minimum",
    "dof": "points − fitted parameters",
}


def _linear_fit(x, y, w, exponent):
    """(χ², ln A, β) of y ≈ ln A − β x weighted by w; β = exponent unless exponent is None."""
    if exponent is None:
        sw, sx, sy = w.sum(), (w * x).sum(), (w * y).sum()
        sxx, sxy = (w * x * x).sum(), (w * x * y).sum()
        det = sw * sxx - sx * sx
        if det <= 0:
            raise ValueError("the points do not determine an exponent (all at one ν?)")
        beta = -(sw * sxy - sx * sy) / det
        ln_a = (sy + beta * sx) / sw
    else:
        beta = exponent
        ln_a = (w * (y + beta * x)).sum() / w.sum()
    chi2 = float((w * (y - ln_a + beta * x) ** 2).sum())
    return chi2, ln_a, beta


def _chi2_at(nu, y, w, exponent, nu_c):
    return _linear_fit(np.log(nu_c - nu), y, w, exponent)


def fit_divergence(nu, q, q_error, exponent=None, max_distance=0.2):
    """Fit q = A (ν_c − ν)^−β (β = exponent if given); returns a dict of the /fits columns
    (without friction, restitution, quantity). Raises ValueError for unusable input."""
    nu, q, q_error = (np.asarray(a, dtype=float) for a in (nu, q, q_error))
    params = 3 if exponent is None else 2
    if len(nu) < params + 1:
        raise ValueError(f"{len(nu)} points cannot fit {params} parameters with a χ² to spare (need {params + 1})")
    if not (np.all(q > 0) and np.all(q_error > 0) and np.all(np.isfinite(q)) and np.all(np.isfinite(q_error))):
        raise ValueError("every value and error must be finite and > 0")
    y = np.log(q)
    w = (q / q_error) ** 2
    nu_max = float(nu.max())
    distances = np.geomspace(MIN_DISTANCE, max_distance, GRID_POINTS)
    profile = np.array([_chi2_at(nu, y, w, exponent, nu_max + d)[0] for d in distances])
    k = int(np.argmin(profile))
    # Golden section on ln d between the grid neighbours of the minimum.
    lo = math.log(distances[max(k - 1, 0)])
    hi = math.log(distances[min(k + 1, GRID_POINTS - 1)])
    f = lambda t: _chi2_at(nu, y, w, exponent, nu_max + math.exp(t))[0]  # noqa: E731
    a, b = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
    fa, fb = f(a), f(b)
    for _ in range(80):
        if fa < fb:
            hi, b, fb = b, a, fa
            a = hi - GOLDEN * (hi - lo)
            fa = f(a)
        else:
            lo, a, fa = a, b, fb
            b = lo + GOLDEN * (hi - lo)
            fb = f(b)
    t_best = 0.5 * (lo + hi)
    chi2, ln_a, beta = _chi2_at(nu, y, w, exponent, nu_max + math.exp(t_best))
    if chi2 > profile[k]:
        t_best = math.log(distances[k])
        chi2, ln_a, beta = profile[k], *_chi2_at(nu, y, w, exponent, nu_max + distances[k])[1:]
    dof = len(nu) - params
    delta = max(1.0, chi2 / dof)
    inside = profile <= chi2 + delta
    result = {
        "points": len(nu),
        "nu_max": nu_max,
        "exponent_fixed": math.nan if exponent is None else float(exponent),
        "exponent": float(beta),
        "amplitude": float(math.exp(ln_a)),
        "chi2": float(chi2),
        "dof": dof,
    }
    if k == GRID_POINTS - 1:
        # The best fit is at the largest distance allowed: no divergence within reach.
        result.update(nu_c=math.inf, nu_c_low=nu_max + float(distances[np.argmax(inside)]), nu_c_high=math.inf)
        return result
    below = np.nonzero(~inside[:k])[0]
    above = np.nonzero(~inside[k:])[0]
    result["nu_c"] = nu_max + math.exp(t_best)
    result["nu_c_low"] = nu_max + float(distances[below[-1] + 1]) if len(below) else nu_max
    result["nu_c_high"] = nu_max + float(distances[k + above[0] - 1]) if len(above) else math.inf
    return result


def read_rows(paths):
    """{(friction, restitution): {"nu": [...], quantity: [...], quantity_error: [...]}} over the
    tables' rows, each run (input path) once."""
    groups, seen = {}, set()
    for path in paths:
        try:
            table = steady_state.read_table(path)
        except KeyError as exc:
            raise ValueError(f"{path}: not a steady_state.py table ({exc})") from exc
        runs, steady = table["runs"], table["steady"]
        missing = [q for q in QUANTITIES if q not in steady]
        if missing:
            raise ValueError(f"{path}: no /steady/{missing[0]}")
        for i, run in enumerate(runs["input"]):
            if run in seen:
                continue
            seen.add(run)
            key = (round(float(runs["friction"][i]), 6), round(float(runs["restitution"][i]), 6))
            g = groups.setdefault(key, {"nu": [], **{k: [] for q in QUANTITIES for k in (q, q + "_error")}})
            g["nu"].append(float(runs["packing_fraction"][i]))
            for q in QUANTITIES:
                g[q].append(float(steady[q][i]))
                g[q + "_error"].append(float(steady[q + "_error"][i]))
    return groups


def analyse(paths, from_nu, exponents, max_distance, friction=None, restitution=None):
    """(the /fits rows for every selected (μ, e) group, quantity and reading; the selected groups
    with fewer than MIN_POINTS runs at ν >= from_nu, as (μ, e, runs), which are not fitted)."""
    groups = read_rows(paths)
    rows, skipped, selected = [], [], 0
    for (mu, e), g in sorted(groups.items()):
        if friction is not None and not math.isclose(mu, friction, abs_tol=1e-6):
            continue
        if restitution is not None and not math.isclose(e, restitution, abs_tol=1e-6):
            continue
        selected += 1
        nu = np.array(g["nu"])
        keep = nu >= from_nu - 1e-9
        if keep.sum() < MIN_POINTS:
            skipped.append((mu, e, int(keep.sum())))
            continue
        for q in QUANTITIES:
            for exponent in [None, *exponents]:
                try:
                    fit = fit_divergence(nu[keep], np.array(g[q])[keep], np.array(g[q + "_error"])[keep],
                                         exponent, max_distance)
                except ValueError as exc:
                    raise ValueError(f"μ = {mu:g}, e = {e:g}, {q}: {exc}") from exc
                rows.append({"friction": mu, "restitution": e, "quantity": q, **fit})
    if not selected:
        raise ValueError("no rows match --friction/--restitution")
    return rows, skipped


def write_table(output, rows, skipped, args, inputs, command_line):
    parameters = {
        "from_nu": args["from_nu"],
        "max_distance": args["max_distance"],
        "exponents": np.array(args["exponent"], dtype=float),
    }
    with outputs.table(output, os.path.abspath(__file__), command_line, parameters,
                       [(p, sha256(p)) for p in inputs]) as f:
        fits = f.create_group("fits")
        outputs.text_dataset(fits, "quantity", [r["quantity"] for r in rows])
        fits["quantity"].attrs["meaning"] = MEANINGS["quantity"]
        # Every column is a number: the quantities fitted (QUANTITIES) are dimensionless.
        for col, meaning in MEANINGS.items():
            if col != "quantity":
                outputs.column(fits, col, [r[col] for r in rows], "1", meaning, dtype=None)
        few = f.create_group("skipped")
        for k, (col, meaning) in enumerate((("friction", "μ of a group not fitted"),
                                            ("restitution", "its e"),
                                            ("points", f"its runs at ν >= from_nu (fewer than {MIN_POINTS})"))):
            outputs.column(few, col, [s[k] for s in skipped], "1", meaning, dtype=int if col == "points" else float)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--friction", type=float, help="fit only the runs at this μ (default: every μ)")
    ap.add_argument("--restitution", type=float, help="fit only the runs at this e (default: every e)")
    ap.add_argument("--from-nu", type=float, default=0.70, help="fit the runs at ν >= this (0.70)")
    ap.add_argument("--exponent", type=float, action="append", default=None,
                    help="also fit with β fixed at this value (repeatable; default 2)")
    ap.add_argument("--max-distance", type=float, default=0.2,
                    help="largest ν_c − max ν considered (0.2)")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("tables", nargs="+", help="steady_state.py tables")
    args = ap.parse_args()
    if args.exponent is None:
        args.exponent = [2.0]
    if not 0 < args.max_distance < 1:
        ap.error("--max-distance must be in (0, 1)")
    if any(not b > 0 for b in args.exponent):
        ap.error("--exponent must be > 0")
    try:
        rows, skipped = analyse(args.tables, args.from_nu, args.exponent, args.max_distance, args.friction, args.restitution)
    except (OSError, KeyError, ValueError) as exc:
        print(f"jamming_point.py: {exc}", file=sys.stderr)
        sys.exit(2)
    write_table(args.output, rows, skipped, vars(args), args.tables, shlex.join(sys.argv))
    for r in rows:
        reading = "β free" if math.isnan(r["exponent_fixed"]) else f"β = {r['exponent_fixed']:g}"
        print(f"jamming_point.py: μ = {r['friction']:g}, e = {r['restitution']:g}, {r['quantity']}, {reading}: "
              f"ν_c = {r['nu_c']:.4f} in [{r['nu_c_low']:.4f}, {r['nu_c_high']:.4f}], β = {r['exponent']:.2f}, "
              f"χ²/dof = {r['chi2']:.1f}/{r['dof']} ({r['points']} runs, densest ν = {r['nu_max']:g})",
              file=sys.stderr)
    for mu, e, n in skipped:
        print(f"jamming_point.py: μ = {mu:g}, e = {e:g}: not fitted, {n} runs at ν >= {args.from_nu:g} "
              f"(needs {MIN_POINTS})", file=sys.stderr)


if __name__ == "__main__":
    main()
