"""Reading gf-kinetic's output (one row per run under /runs, one per equilibrium run under
/equilibrium; layout in docs/file-format.md) for the chapter-6 figures and report, and the
sweep-level statements the report makes from it: where the static and collisional stresses
agree, how far the Enskog pressure holds, which shear-stress prediction the dilute data follow,
and the velocity correlations beside the shear-stress error. Nothing is recomputed from the
runs: every per-run number is gf-kinetic's; what is computed here is the comparison across ν.

The thesis colours the points of Figs 6.1-6.3 by ξ/ξ_el (l. 735): that ratio is gf-correlate's
(/correlation/xi_abs_ratio, as in the chapter-5 figures), matched to gf-kinetic's rows by the
input path both programs record."""
import math
import os

import h5py
import numpy as np

from granflow import correlation_table as ct
from granflow.hdf5 import read_attrs, read_group

NAN = float("nan")
# ξ/ξ_el above which a point is drawn filled: the thesis' bound of the dilute regime (l. 735).
XI_THRESHOLD = 1.25
# Two stresses "agree within errors" when they differ by at most this many combined standard errors.
AGREE_SIGMAS = 2.0
# The pressure prediction "holds" where |p^s/p_enskog − 1| is at most this.
PRESSURE_TOLERANCE = 0.05


def read_table(path):
    """Every dataset of a gf-kinetic output by group (runs, equilibrium), the groups' attributes
    under "attrs", and /parameters."""
    table = {"path": path}
    with h5py.File(path, "r") as f:
        if "runs" not in f:
            raise SystemExit(f"{path}: no /runs group: not a gf-kinetic table")
        for group in ("runs", "equilibrium"):
            if group in f:
                table[group] = {**read_group(f[group]), "attrs": read_attrs(f[group])}
        table["parameters"] = read_attrs(f["parameters"]) if "parameters" in f else {}
    return table


def column(table, name):
    """A /runs dataset as floats; NaN everywhere if the table lacks it."""
    runs = table["runs"]
    n = len(runs["packing_fraction"])
    return np.asarray(runs[name], dtype=float) if name in runs else np.full(n, NAN)


def select(table, restitution, tolerance=1e-6):
    """Rows at restitution e (every friction), in increasing ν."""
    runs = table["runs"]
    rows = np.flatnonzero(np.abs(np.asarray(runs["restitution"], dtype=float) - restitution) <= tolerance)
    return rows[np.argsort(np.asarray(runs["packing_fraction"], dtype=float)[rows], kind="stable")]


def _key(path):
    return os.path.normpath(os.path.abspath(path))


def xi_ratio(kinetic, correlate):
    """Per row of the kinetic table: gf-correlate's ξ_|C|/ξ_el of the same run (matched by input
    path), its error and whether gf-correlate could measure it; NaN, NaN, False for a run the
    correlate table does not have."""
    res = ct.analyse(correlate)
    where = {_key(p): i for i, p in enumerate(correlate["runs"]["input"])}
    n = len(kinetic["runs"]["packing_fraction"])
    ratio, error, measurable = np.full(n, NAN), np.full(n, NAN), np.zeros(n, dtype=bool)
    for k, path in enumerate(kinetic["runs"]["input"]):
        i = where.get(_key(path))
        if i is not None:
            ratio[k], error[k], measurable[k] = res["ratio"][i], res["ratio_error"][i], res["measurable"][i]
    return ratio, error, measurable


def filled(ratio, measurable=None, threshold=XI_THRESHOLD):
    """The thesis' colouring: True (filled) where ξ/ξ_el > threshold, or where gf-correlate found
    the correlations reaching the box (not measurable: ξ at least the cell's, beyond the dilute
    regime); False (open) otherwise, and for a run without a ξ (NaN and no flag)."""
    ratio = np.asarray(ratio, dtype=float)
    out = np.isfinite(ratio) & (ratio > threshold)
    if measurable is not None:
        out |= np.isfinite(ratio) & ~np.asarray(measurable, dtype=bool)
    return out


def agree(a, a_error, b, b_error, sigmas=AGREE_SIGMAS):
    """Per element: |a − b| ≤ sigmas·√(a_error² + b_error²) (False where anything is NaN)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    tol = sigmas * np.hypot(np.asarray(a_error, dtype=float), np.asarray(b_error, dtype=float))
    with np.errstate(invalid="ignore"):
        return np.isfinite(a) & np.isfinite(b) & np.isfinite(tol) & (np.abs(a - b) <= tol)


def dilute_range(nu, ok):
    """The largest ν up to which `ok` holds at every ν from the most dilute one on (NaN if it
    fails at the most dilute ν already), and the ν beyond it where it holds again (a list)."""
    nu, ok = np.asarray(nu, dtype=float), np.asarray(ok, dtype=bool)
    order = np.argsort(nu, kind="stable")
    nu, ok = nu[order], ok[order]
    if len(nu) == 0 or not ok[0]:
        return NAN, [float(v) for v in nu[ok]]
    first_fail = np.flatnonzero(~ok)
    last = len(nu) - 1 if len(first_fail) == 0 else first_fail[0] - 1
    return float(nu[last]), [float(v) for v in nu[last + 1 :][ok[last + 1 :]]]


def pressures_agree(table, rows):
    """p^bc = p^s within errors, per row."""
    return agree(
        column(table, "p_static")[rows],
        column(table, "p_static_error")[rows],
        column(table, "p_collisional")[rows],
        column(table, "p_collisional_error")[rows],
    )


def pressure_prediction_holds(table, rows, tolerance=PRESSURE_TOLERANCE):
    """|p^s/p_enskog − 1| ≤ tolerance per row (eq. 6.9: p^s/p⁰ against (1+e)χν), and the ratio."""
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = column(table, "p_static")[rows] / column(table, "p_enskog")[rows]
        return np.isfinite(ratio) & (np.abs(ratio - 1) <= tolerance), ratio


def shear_error(table, rows, prediction):
    """(s_prediction − s^s)/s^s per row; prediction "s_enskog_thesis" or "s_enskog_2d"."""
    with np.errstate(invalid="ignore", divide="ignore"):
        s = column(table, "s_static")[rows]
        return (column(table, prediction)[rows] - s) / s


def proportionality(x, y):
    """Pearson's r between x and y over the finite pairs, and their number (NaN below 3 pairs or
    without spread)."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    ok = np.isfinite(x) & np.isfinite(y)
    if ok.sum() < 3 or np.std(x[ok]) == 0 or np.std(y[ok]) == 0:
        return NAN, int(ok.sum())
    return float(np.corrcoef(x[ok], y[ok])[0, 1]), int(ok.sum())


def fmt_pm(value, error):
    """value ± error, or "not measured" where the value is NaN."""
    if not np.isfinite(value):
        return "not measured"
    return ct.fmt_pm(value, error)


def fmt_nu(value):
    return "none" if not np.isfinite(value) else f"{value:.3f}"


def fmt_percent(value):
    """A relative change in per cent with its sign, or "not measured" for NaN."""
    return "not measured" if not np.isfinite(value) else f"{100 * value:+.2f} %"


def fmt_ratio(value):
    return "not measured" if not np.isfinite(value) else f"{value:.3f}"


def sign_word(value, error, baseline=0.0, sigmas=AGREE_SIGMAS):
    """"positive"/"negative" if value − baseline is beyond sigmas·error from zero, "zero within
    errors" otherwise, "not measured" for NaN."""
    if not np.isfinite(value):
        return "not measured"
    d = value - baseline
    if np.isfinite(error) and abs(d) <= sigmas * error:
        return "zero within errors"
    return "positive" if d > 0 else "negative"


def closer_prediction(ratio_thesis, ratio_2d):
    """Which of the two s-predictions the measured s^s is closer to (in |log(s^s/s_pred)|)."""
    scores = {}
    for name, r in (("eq. 6.10 as printed", ratio_thesis), ("2D Garzó–Dufty", ratio_2d)):
        if np.isfinite(r) and r > 0:
            scores[name] = abs(math.log(r))
    if not scores:
        return "not measured"
    return min(scores, key=scores.get)
