"""Reading gf-correlate's output (one row per run, see lib/correlation/report.hpp) for the
chapter-5 figures and report.

The correlation length of the figures is gf-correlate's ξ_|C| (/correlation/xi_abs): the
decay length of |C̄(ℓ)|, eq. 5.2 on |C̄| with a noise floor, exact bin integrals and
block-jackknife errors, per run and per direction, with the box-spanning flag
(/correlation/measurable), ξ_el (/correlation/xi_abs_el, the pooled --reference runs),
ξ_|C|/ξ_el and ν_bc(e, μ) over the measurable runs (/sweep/*_abs); its definition is in
lib/correlation/decay_length.hpp and the table's /correlation attributes. gf-correlate's
eq.-5.2 ξ on the signed C̄ (/correlation/xi, /sweep/nu_bc) is kept beside it: a harmonic
mean of contact distances in dilute flows, ill-conditioned where C̄ changes sign. Nothing
is recomputed here: analyse() gathers the program's values under the names the figure
scripts use. What remains computed here is sweep-level presentation: the pooled eq.-5.3
fit of Fig. 5.6 over many runs, and the P(f) rule check.
"""
import math

import h5py
import numpy as np

from granflow.hdf5 import read_attrs, read_group

NAN = float("nan")


def read_table(path):
    """Every dataset of a gf-correlate output, by group, plus the groups' attributes."""
    table = {"path": path}
    with h5py.File(path, "r") as f:
        for group in ("runs", "correlation", "forces", "sweep", "reference", "clusters"):
            if group in f:
                table[group] = {**read_group(f[group]), "attrs": read_attrs(f[group])}
        table["parameters"] = read_attrs(f["parameters"]) if "parameters" in f else {}
    return table


def select(table, tolerance=1e-6, **criteria):
    """Rows whose run columns (packing_fraction, restitution, friction, ...) equal the given
    values, in increasing ν."""
    runs = table["runs"]
    keep = np.ones(len(runs["packing_fraction"]), dtype=bool)
    for name, value in criteria.items():
        keep &= np.abs(runs[name] - value) <= tolerance
    rows = np.flatnonzero(keep)
    return rows[np.argsort(runs["packing_fraction"][rows], kind="stable")]


def nearest(table, nu, **criteria):
    """The row with the given parameters whose ν is closest to nu (None if no such row)."""
    rows = select(table, **criteria)
    if len(rows) == 0:
        return None
    return int(rows[np.argmin(np.abs(table["runs"]["packing_fraction"][rows] - nu))])


def mean_diameter(table):
    return float(table["correlation"]["attrs"]["mean_diameter"])


def rebin(r, c, error, factor):
    """Merge `factor` consecutive radial bins of a density per unit area: the merged bins'
    centres, the area-weighted mean (annulus areas ∝ ℓ at the bin centre) and errors added in
    quadrature. Drops a partial last group."""
    n = (len(r) // factor) * factor
    r, c, error = (np.asarray(a, dtype=float)[:n].reshape(-1, factor) for a in (r, c, error))
    total = r.sum(axis=1)  # annulus area ∝ centre radius for equal widths
    return (r.mean(axis=1), (c * r).sum(axis=1) / total, np.sqrt(((error * r) ** 2).sum(axis=1)) / total)


def reference_rows(table):
    """Rows of the table that are gf-correlate's --reference runs (matched by path)."""
    if "reference" not in table:
        return np.array([], dtype=int)
    inputs = list(table["runs"]["input"])
    return np.array([inputs.index(p) for p in table["reference"]["input"] if p in inputs], dtype=int)


STATUS = {0: "bracketed", 1: "all_above", 2: "all_below", 3: "too_few", 4: "only_downward"}


def fit_anisotropy(theta, y, y_error, sector_width):
    """Weighted least-squares fit of eq. 5.3 in the normalised form
    y(θ) = 2π ξ(θ)/ξ = 1 − a0 sin 2(θ − θ0) = 1 − A sin 2θ + B cos 2θ (A = a0 cos 2θ0,
    B = a0 sin 2θ0), linear in (A, B), to sector averages (factor sin Δθ / Δθ on the
    harmonics). Returns a0, θ0 ∈ (−π/2, π/2], their errors and χ²/dof."""
    theta, y, y_error = (np.asarray(a, dtype=float).ravel() for a in (theta, y, y_error))
    ok = np.isfinite(theta) & np.isfinite(y) & np.isfinite(y_error) & (y_error > 0)
    theta, y, y_error = theta[ok], y[ok], y_error[ok]
    if len(y) < 3:
        return dict(a0=NAN, a0_error=NAN, theta0=NAN, theta0_error=NAN, chi2_dof=NAN)
    damp = math.sin(sector_width) / sector_width if sector_width > 0 else 1.0
    design = np.column_stack((-damp * np.sin(2 * theta), damp * np.cos(2 * theta))) / y_error[:, None]
    rhs = (y - 1) / y_error
    (a, b), *_ = np.linalg.lstsq(design, rhs, rcond=None)
    dof = max(len(y) - 2, 1)
    chi2 = float(np.sum((design @ np.array([a, b]) - rhs) ** 2)) / dof
    cov = np.linalg.inv(design.T @ design) * max(1.0, chi2)
    a0 = math.hypot(a, b)
    theta0 = 0.5 * math.atan2(b, a)
    if a0 > 0:
        ja = np.array([a / a0, b / a0])
        jt = np.array([-b, a]) / (2 * a0**2)
        a0_err, t_err = math.sqrt(ja @ cov @ ja), math.sqrt(jt @ cov @ jt)
    else:
        a0_err, t_err = math.sqrt(cov[0, 0]), NAN
    return dict(a0=a0, a0_error=a0_err, theta0=theta0, theta0_error=t_err, chi2_dof=chi2)


def eq53(theta, a0, theta0):
    """2π ξ(θ)/ξ of eq. 5.3."""
    return 1 - a0 * np.sin(2 * (np.asarray(theta) - theta0))


def peak_agreement(ratio, peak, threshold=1.25):
    """Per run: does gf-correlate's P(f) decision agree with the thesis' rule (peak at f > 0
    iff ξ/ξ_el < threshold)? Returns an array of True/False (NaN ratios: False)."""
    ratio, peak = np.asarray(ratio, dtype=float), np.asarray(peak)
    expected = ratio < threshold
    return np.isfinite(ratio) & (expected == (peak == 1))


def analyse(table):
    """gf-correlate's ξ_|C| results under the names the figures and the report use: per run
    xi, xi_error, tail_share, measurable, ratio, ratio_error; xi_el, xi_el_error; per (e, μ)
    series (dicts with nu_bc, nu_bc_error, nu_below, nu_above, status name, runs = measurable
    runs); the settings (threshold, max_tail_share, k = abs_noise, factor = radial bins per
    coarse bin, bin_width = the coarse bin width)."""
    cor, runs = table["correlation"], table["runs"]
    missing = [
        name for name in ("xi_abs", "xi_abs_error", "xi_abs_tail", "measurable", "xi_abs_ratio") if name not in cor
    ]
    if missing:
        raise SystemExit(
            f"{table['path']}: no /correlation/{missing[0]}: made by a gf-correlate without xi_abs; "
            "re-run gf-correlate (make ch5-files)"
        )
    attrs = cor["attrs"]
    n = len(runs["packing_fraction"])
    sweep = table.get("sweep", {})
    threshold = float(sweep.get("attrs", {}).get("threshold", 1.25))
    series = []
    if "status_abs" in sweep:
        for k in range(len(sweep["restitution"])):
            series.append(
                {
                    "restitution": float(sweep["restitution"][k]),
                    "friction": float(sweep["friction"][k]),
                    "nu_bc": float(sweep["nu_bc_abs"][k]),
                    "nu_bc_error": float(sweep["nu_bc_abs_error"][k]),
                    "nu_below": float(sweep["nu_below_abs"][k]),
                    "nu_above": float(sweep["nu_above_abs"][k]),
                    "status": STATUS.get(int(sweep["status_abs"][k]), "?"),
                    "runs": int(sweep["runs_abs"][k]),
                }
            )
    bin_width = float(attrs["bin_width"])
    coarse = float(attrs.get("abs_bin_width", bin_width))
    return {
        "xi": np.asarray(cor["xi_abs"], dtype=float),
        "xi_error": np.asarray(cor["xi_abs_error"], dtype=float),
        "tail_share": np.asarray(cor["xi_abs_tail"], dtype=float),
        "measurable": np.asarray(cor["measurable"]).astype(bool).reshape(n),
        "max_tail_share": float(attrs.get("abs_max_tail_share", 0.05)),
        "xi_el": float(cor["xi_abs_el"]),
        "xi_el_error": float(cor["xi_abs_el_error"]),
        "ratio": np.asarray(cor["xi_abs_ratio"], dtype=float),
        "ratio_error": np.asarray(cor["xi_abs_ratio_error"], dtype=float),
        "reference_rows": reference_rows(table),
        "series": series,
        "threshold": threshold,
        "k": float(attrs.get("abs_noise", float("nan"))),
        "threshold_kind": str(attrs.get("abs_threshold", "soft")),
        "factor": max(1, int(round(coarse / bin_width))),
        "bin_width": coarse,
    }


def fmt_pm(value, error):
    """value ± error with the error's two significant digits (plain value if no error)."""
    if not np.isfinite(value):
        return "nan"
    if not (np.isfinite(error) and error > 0):
        return f"{value:.4g}"
    digits = max(0, 1 - int(math.floor(math.log10(error))))
    return f"{value:.{digits}f} ± {error:.{digits}f}"
