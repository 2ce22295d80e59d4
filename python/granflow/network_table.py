"""Reading gf-network's output (one row per run under /runs and /prediction, the pooled angular
and deflection histograms under /histograms; layout in docs/file-format.md) for the chapter-6
force-network figures (thesis Figs 6.5-6.8) and report, and the sweep-level statements made
from it: the collapse of Fig. 6.8 (slope and scatter of log lhs against log rhs per equation
and reading), the range of Φ, Ψ < Φ, the size of the 4θ components, z at two time steps and the
identity s^bc/p^bc = −2χ12. Nothing is recomputed from the runs: every per-run number is
gf-network's; what is computed here is the comparison across runs."""
import math

import h5py
import numpy as np

from granflow import correlation_table as ct
from granflow.hdf5 import read_attrs, read_group

NAN = float("nan")
# Eqs. 6.27-6.29: the suffix of the /prediction datasets, the thesis' equation, its left-hand side.
EQUATIONS = (
    ("pressure", "6.27", "(p^s − p^bc)/p^bc"),
    ("shear", "6.28", "(s^s − s^bc)/p^bc"),
    ("xx", "6.29", "(Σ₁₁^s − Σ₁₁^bc)/p^bc"),
)
# The readings of the right-hand sides: dataset suffix and what it means (contract of gf-network).
READINGS = (
    ("", "z over all grains, Φ, Ψ = 2⟨…⟩, sums continued to non-integer ξ/ξ_el − 1"),
    ("_floor", "the sums up to ⌊ξ/ξ_el − 1⌋"),
    ("_active", "z over grains with a long-lived contact"),
    ("_unit", "Φ = ⟨cos x⟩, Ψ = ⟨cos x cos 2x⟩ (without the factor 2)"),
)
# The thesis' Φ (Fig. 6.7, l. 953) and its bound on the next Fourier order (l. 910).
THESIS_PHI = 0.83
THESIS_NEXT_ORDER = 0.01
# Two values "agree within errors" when they differ by at most this many combined standard errors.
AGREE_SIGMAS = 2.0
# A pair of rows (default step, half step) has dt ratios within this relative tolerance of 2.
STEP_RATIO_TOLERANCE = 1e-6


def read_table(path):
    """Every dataset of a gf-network output by group (runs, prediction, histograms), the groups'
    attributes under "attrs", and /parameters; SystemExit (one line) if it is not one."""
    table = {"path": path}
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise SystemExit(f"{path}: cannot read: {exc}") from None
    with f:
        for group in ("runs", "prediction", "histograms"):
            if group not in f:
                raise SystemExit(f"{path}: no /{group} group: not a gf-network table")
            table[group] = {**read_group(f[group]), "attrs": read_attrs(f[group])}
        table["parameters"] = read_attrs(f["parameters"]) if "parameters" in f else {}
    return table


def rows(table):
    """The number of runs (rows) of a table."""
    return len(table["runs"]["packing_fraction"])


def column(table, name, group="runs"):
    """A per-run dataset of /runs (or /prediction) as floats; NaN everywhere if the table lacks it."""
    values = table[group]
    return np.asarray(values[name], dtype=float) if name in values else np.full(rows(table), NAN)


def select(table, restitution, tolerance=1e-6):
    """Rows at restitution e, in increasing ν."""
    e = column(table, "restitution")
    found = np.flatnonzero(np.abs(e - restitution) <= tolerance)
    return found[np.argsort(column(table, "packing_fraction")[found], kind="stable")]


def restitutions(table):
    """The restitutions of the table, decreasing (the thesis' legend order)."""
    return sorted({float(e) for e in column(table, "restitution")}, reverse=True)


def nearest(table, restitution, nu):
    """The row at the restitution nearest to `restitution` whose ν is nearest to nu."""
    e = column(table, "restitution")
    closest = e[np.argmin(np.abs(e - restitution))]
    found = select(table, closest)
    return int(found[np.argmin(np.abs(column(table, "packing_fraction")[found] - nu))])


def lhs_rhs(table, equation, reading=""):
    """Left- and right-hand sides of one equation ("pressure", "shear", "xx") in one reading
    ("", "_floor", "_active", "_unit"), with their errors: (lhs, lhs_error, rhs, rhs_error)."""
    lhs = "lhs_" + equation
    rhs = "rhs_" + equation + reading
    return tuple(column(table, name, "prediction") for name in (lhs, lhs + "_error", rhs, rhs + "_error"))


def collapse(lhs, rhs):
    """Fig. 6.8's collapse as numbers, over the rows with lhs > 0 and rhs > 0 (both finite): the
    least-squares slope and intercept of log10 lhs against log10 rhs (NaN below two rows or
    without spread in rhs), the scatter (rms of log10(lhs/rhs) in dex: 0 for a perfect collapse
    onto y = x), the rows used, the rows left out because a side is finite but not positive,
    the rows without a value (NaN: no ξ/ξ_el), and the decades rhs and lhs span."""
    lhs, rhs = np.asarray(lhs, dtype=float), np.asarray(rhs, dtype=float)
    finite = np.isfinite(lhs) & np.isfinite(rhs)
    with np.errstate(invalid="ignore"):
        used = finite & (lhs > 0) & (rhs > 0)
    out = {
        "used": int(used.sum()),
        "non_positive": int((finite & ~used).sum()),
        "missing": int((~finite).sum()),
        "slope": NAN,
        "intercept": NAN,
        "scatter": NAN,
        "decades_rhs": NAN,
        "decades_lhs": NAN,
    }
    if out["used"] == 0:
        return out
    x, y = np.log10(rhs[used]), np.log10(lhs[used])
    out["scatter"] = float(np.sqrt(np.mean((y - x) ** 2)))
    out["decades_rhs"] = float(x.max() - x.min())
    out["decades_lhs"] = float(y.max() - y.min())
    if out["used"] >= 2 and np.ptp(x) > 0:
        slope, intercept = np.polyfit(x, y, 1)
        out["slope"], out["intercept"] = float(slope), float(intercept)
    return out


def collapse_table(table):
    """collapse() for every equation × reading: a list of dicts with "equation", "number" (the
    thesis' equation), "reading" (suffix) and collapse()'s fields."""
    out = []
    for equation, number, _ in EQUATIONS:
        for reading, _ in READINGS:
            lhs, _, rhs, _ = lhs_rhs(table, equation, reading)
            out.append({"equation": equation, "number": number, "reading": reading, **collapse(lhs, rhs)})
    return out


def largest_abs(table, names):
    """The largest |value| over the rows and the columns `names` (finite values only): (value,
    error, name, row); (NaN, NaN, None, None) if there is none."""
    best = (NAN, NAN, None, None)
    for name in names:
        values, errors = column(table, name), column(table, name + "_error")
        for r in np.flatnonzero(np.isfinite(values)):
            if not np.isfinite(best[0]) or abs(values[r]) > abs(best[0]):
                best = (float(values[r]), float(errors[r]), name, int(r))
    return best


def count_at_least(table, names, bound):
    """Rows where any of the columns `names` has |value| ≥ bound, and the rows with a finite value."""
    values = np.column_stack([column(table, n) for n in names])
    finite = np.isfinite(values).any(axis=1)
    with np.errstate(invalid="ignore"):
        large = (np.abs(values) >= bound).any(axis=1)
    return int(large.sum()), int(finite.sum())


def psi_below_phi(table):
    """Rows with Ψ < Φ, rows with both finite, and the rows (indices) where Ψ ≥ Φ."""
    phi, psi = column(table, "Phi"), column(table, "Psi")
    finite = np.isfinite(phi) & np.isfinite(psi)
    below = finite & (psi < phi)
    return int(below.sum()), int(finite.sum()), np.flatnonzero(finite & ~below)


def step_pairs(table, ratio=2.0, tolerance=1e-6):
    """Pairs (default-step row, smaller-step row) of runs with equal ν, e, μ, e_t and γ̇ whose dt
    differ by `ratio` (the inset of Fig. 6.7: z at the default step and at half of it)."""
    keys = ("packing_fraction", "restitution", "friction", "tangential_restitution", "rate")
    cols = {k: column(table, k) for k in keys}
    dt = column(table, "dt")
    out = []
    for i in range(rows(table)):
        for j in range(rows(table)):
            if i == j or not (dt[i] > 0 and dt[j] > 0):
                continue
            same = all(
                (np.isnan(cols[k][i]) and np.isnan(cols[k][j])) or abs(cols[k][i] - cols[k][j]) <= tolerance
                for k in keys
            )
            if same and abs(dt[i] / dt[j] / ratio - 1) <= STEP_RATIO_TOLERANCE:
                out.append((i, j))
    return sorted(out, key=lambda p: (-cols["restitution"][p[0]], cols["packing_fraction"][p[0]]))


def difference_sigmas(a, a_error, b, b_error):
    """(a − b)/√(a_error² + b_error²); NaN where it is undefined, ±inf for a difference without error."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    sigma = np.hypot(np.asarray(a_error, dtype=float), np.asarray(b_error, dtype=float))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(sigma > 0, (a - b) / sigma, np.where(a == b, 0.0, np.sign(a - b) * np.inf))


def identity_deviation(table, frames=False):
    """s^bc/p^bc (the rows' shear_ratio_collisional, or the frames' shear_ratio_collisional_frames)
    against −2χ12 (the identity holds when σ(θ) is constant), per row: (ratio, its error, −2χ12,
    its error, difference in combined errors)."""
    name = "shear_ratio_collisional" + ("_frames" if frames else "")
    ratio, ratio_error = column(table, name), column(table, name + "_error")
    target, target_error = -2 * column(table, "chi_12"), 2 * column(table, "chi_12_error")
    return ratio, ratio_error, target, target_error, difference_sigmas(ratio, ratio_error, target, target_error)


def bound_excess(table):
    """Eq. 6.27's bound: with 0 ≤ M = min[Φ(z − 1), 1] ≤ 1 its right-hand side is at most
    ξ/ξ_el − 1 (every link passes its whole force on), whatever z, Φ and the reading of the
    sums. Per row: (lhs_pressure − sum_limit) in combined errors (lhs_pressure_error and
    xi_ratio_error, ∂sum_limit/∂(ξ/ξ_el) = 1); NaN without a ξ/ξ_el."""
    lhs, lhs_error = column(table, "lhs_pressure", "prediction"), column(table, "lhs_pressure_error", "prediction")
    limit, limit_error = column(table, "sum_limit", "prediction"), column(table, "xi_ratio_error", "prediction")
    return difference_sigmas(lhs, lhs_error, limit, limit_error)


def largest_finite(values):
    """The index of the largest finite |value| (None if there is none)."""
    values = np.asarray(values, dtype=float)
    finite = np.flatnonzero(np.isfinite(values))
    if len(finite) == 0:
        return None
    return int(finite[np.argmax(np.abs(values[finite]))])


def value_range(values):
    """(min, max) over the finite values, (NaN, NaN) if there is none."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    return (float(values.min()), float(values.max())) if len(values) else (NAN, NAN)


def fmt_pm(value, error):
    """value ± error, or "not measured" where the value is NaN."""
    if not np.isfinite(value):
        return "not measured"
    return ct.fmt_pm(value, error)


def fmt_number(value, digits=3):
    return "not measured" if value is None or not np.isfinite(value) else f"{value:.{digits}f}"


def fmt_sigmas(value):
    if not np.isfinite(value):
        return "not measured" if math.isnan(value) else ("+∞" if value > 0 else "−∞")
    return f"{value:+.1f}σ".replace("-", "−")
