"""Reading gf-stz fit's output (/runs: one row per shear run and incline point; /fit: one row per
friction coefficient; layout in docs/file-format.md) for the chapter-6 STZ figures (thesis Figs
6.10, 6.11) and report, and the STZ flowing branch (eq. 6.36) drawn from a fit's coefficients.
Nothing is refitted here: every coefficient and residual is gf-stz's."""
import math

import h5py
import numpy as np

from granflow.hdf5 import read_attrs, read_group

NAN = float("nan")
# Two friction coefficients are the same when they differ by less than this.
FRICTION_TOLERANCE = 1e-9


def read_table(path):
    """{"runs": {...}, "fit": {...}, "fit_attrs": {...}, "parameters": {...}} of a gf-stz fit
    output; SystemExit (one line naming the file) if it is not one."""
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise SystemExit(f"{path}: cannot read: {exc}") from None
    with f:
        for group in ("runs", "fit"):
            if group not in f:
                raise SystemExit(f"{path}: no /{group} group: not a gf-stz fit output")
        table = {
            "path": path,
            "runs": read_group(f["runs"]),
            "fit": read_group(f["fit"]),
            "fit_attrs": read_attrs(f["fit"]),
            "parameters": read_attrs(f["parameters"]) if "parameters" in f else {},
        }
    for name in ("kind", "friction", "restitution", "rate_R_over_sqrt_T", "s_over_p", "dense", "fitted"):
        if name not in table["runs"]:
            raise SystemExit(f"{path}: no /runs/{name}: not a gf-stz fit output")
    for name in ("friction", "A", "kappa", "zeta", "tan_theta_star"):
        if name not in table["fit"]:
            raise SystemExit(f"{path}: no /fit/{name}: not a gf-stz fit output")
    return table


def column(table, name, group="runs"):
    """A column of /runs (or /fit) as float; NaN everywhere if the table lacks it."""
    g = table[group]
    n = len(g["friction"])
    return np.asarray(g[name], dtype=float) if name in g else np.full(n, NAN)


def kinds(table):
    return np.asarray(table["runs"]["kind"]).astype(str)


def same(a, b):
    return np.abs(np.asarray(a, dtype=float) - b) < FRICTION_TOLERANCE


def fit_row(table, friction):
    """The /fit row of that friction coefficient, or None."""
    rows = np.flatnonzero(same(column(table, "friction", "fit"), friction))
    return int(rows[0]) if len(rows) else None


def frictions(table):
    """The friction coefficients with a fit, increasing."""
    return sorted(float(m) for m in column(table, "friction", "fit"))


def fit_restitution(table):
    value = table["fit_attrs"].get("fit_restitution", 0.0)
    return float(value)


def stz_rate(A, kappa, zeta, mu):
    """x(μ) = A [sinh(κμ) − cosh(κμ)/(ζμ)], eq. 6.36."""
    mu = np.asarray(mu, dtype=float)
    return A * (np.sinh(kappa * mu) - np.cosh(kappa * mu) / (zeta * mu))


def curve(table, row, x_max, points=400):
    """(x, μ) of the flowing branch of /fit row `row`, from x = 0 (μ = tanθ*) to x_max,
    parametric in μ; empty arrays if the fit's coefficients are not finite."""
    A, kappa, zeta, t = (column(table, n, "fit")[row] for n in ("A", "kappa", "zeta", "tan_theta_star"))
    if not all(math.isfinite(v) and v > 0 for v in (A, kappa, zeta, t)) or not x_max > 0:
        return np.zeros(0), np.zeros(0)
    hi = t
    # x grows without bound above tanθ*: double the span until it passes x_max.
    for _ in range(60):
        hi = t + 2 * (hi - t) if hi > t else t * 1.01
        if stz_rate(A, kappa, zeta, hi) >= x_max:
            break
    mu = np.linspace(t, hi, points)
    x = stz_rate(A, kappa, zeta, mu)
    keep = x <= x_max
    return np.concatenate([[0.0], x[keep][1:]]), np.concatenate([[t], mu[keep][1:]])


def rms(values):
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    return float(np.sqrt(np.mean(values**2))) if len(values) else NAN


def fmt_pm(value, error, digits=3):
    """value ± error with `digits` significant digits of the value ("–" when not finite)."""
    if value is None or not math.isfinite(value):
        return "–"
    if error is None or not math.isfinite(error):
        return f"{value:.{digits}g}"
    return f"{value:.{digits}g} ± {error:.2g}"


def fmt(value, digits=3):
    return f"{value:.{digits}g}" if value is not None and math.isfinite(value) else "–"
