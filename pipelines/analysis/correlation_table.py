"""correlation_table.py: read gf-correlate's output (one row per run, see lib/correlation/
report.hpp) for the chapter-5 figures and report, and the few sweep-level steps done here.

The pipeline-level estimator. gf-correlate's ξ is eq. 5.2 on the signed C̄(ℓ):
Σw / Σ(w/ℓ) over all pairs within ℓ_max. In dilute flows every w = F^i·F^j < 0 (binary
collisions) and this is a harmonic mean of contact distances; in dense flows C̄ changes
sign (positive near contact, a long negative tail: inside every cluster Σ_i F^i = 0, so
the pair sum over a cluster is −W/2), the denominator crosses zero and ξ diverges or
turns negative at finite ℓ_max (quick runs: ν = 0.8, e = 0 gives ξ = 194 ± 2400). The
thesis reads ξ as the decay length of |C(ℓ)| ("C(ℓ) ∼ exp(−ℓ/ξ)", lines e^{−ℓ/ξ} through
log|C| in Fig. 5.2); for |C̄| = A e^{−ℓ/ξ}, ∫ℓ|C̄|dℓ / ∫|C̄|dℓ = ξ exactly. So the figures use

    ξ_|C| = Σ_b ℓ_b a_b / Σ_b a_b,   a_b = max(|C̄_b| − k·δC̄_b, 0)

on radial bins merged `factor` at a time (C̄ area-weighted, errors in quadrature), where
δC̄_b is gf-correlate's jackknife error: soft thresholding at k standard errors removes the
noise floor that |C̄| would otherwise integrate (ℓ-weighted, it would dominate). Its error
is propagated to first order treating bins as independent (∂ξ/∂a_b = (ℓ_b − ξ)/Σa).
In the dilute limit (all w < 0) it reduces to the force-weighted mean contact distance.
Where the network spans the cell, C̄ keeps a plateau up to ℓ_max and ξ_|C| measures the box:
runs with more than 5 % of ∫ℓa dℓ beyond 2ℓ_max/3 (tail_share) are flagged not measurable
(the thesis' "ξ is too large to be measured") and left out of ν_bc.
ξ_el is the mean ξ_|C| of the reference runs (gf-correlate's --reference, which must also be
rows of the table); ν_bc(e, μ) is found on ξ_|C|/ξ_el exactly as gf-correlate does on its
ξ (lib/correlation/sweep.hpp): first upward crossing of the threshold in ν, linear
interpolation, first-order error.
"""
import math

import h5py
import numpy as np

NAN = float("nan")


def _decode(a):
    return np.array([x.decode() if isinstance(x, bytes) else str(x) for x in a])


def read_table(path):
    """Every dataset of a gf-correlate output, by group, plus the groups' attributes."""
    table = {"path": path}
    with h5py.File(path, "r") as f:
        for group in ("runs", "correlation", "forces", "sweep", "reference", "clusters"):
            if group not in f:
                continue
            g = {}
            for name, d in f[group].items():
                value = d[()]
                g[name] = _decode(value) if d.dtype.kind in "SO" else np.asarray(value)
            g["attrs"] = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f[group].attrs.items()}
            table[group] = g
        table["parameters"] = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f["parameters"].attrs.items()} \
            if "parameters" in f else {}
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


def xi_magnitude(r, c, error, k=2.0, factor=5):
    """ξ_|C| (module docstring) and its first-order error, from one row of C̄ and δC̄."""
    r, c, error = rebin(r, c, error, factor)
    ok = np.isfinite(c) & np.isfinite(error)
    r, c, error = r[ok], c[ok], error[ok]
    a = np.maximum(np.abs(c) - k * error, 0.0)
    total = a.sum()
    if not total > 0:
        return NAN, NAN
    xi = float((r * a).sum() / total)
    used = a > 0
    err = float(np.sqrt((((r[used] - xi) / total) ** 2 * error[used] ** 2).sum()))
    return xi, err


def magnitude_lengths(table, k=2.0, factor=5):
    """ξ_|C| and its error for every row of the table."""
    cor = table["correlation"]
    rows = [xi_magnitude(cor["r"], cor["C"][i], cor["C_error"][i], k, factor) for i in range(len(cor["C"]))]
    return np.array([x for x, _ in rows]), np.array([e for _, e in rows])


def tail_share(r, c, error, k=2.0, factor=5, outer=2 / 3):
    """Share of ∫ℓ a dℓ (the numerator of ξ_|C|) coming from ℓ > outer·ℓ_max. Where the force
    network spans the box, C̄ keeps a plateau up to ℓ_max (the sum rule spreads −W/2 over the
    whole cell) and ξ_|C| measures the box, not the network: the thesis' "ξ is too large to be
    measured". NaN without signal."""
    r, c, error = rebin(r, c, error, factor)
    ok = np.isfinite(c) & np.isfinite(error)
    r, c, error = r[ok], c[ok], error[ok]
    a = r * np.maximum(np.abs(c) - k * error, 0.0)
    total = a.sum()
    return float(a[r > outer * (r[-1] + 0.5 * (r[1] - r[0]))].sum() / total) if total > 0 else NAN


def reference_rows(table):
    """Rows of the table that are gf-correlate's --reference runs (matched by path)."""
    if "reference" not in table:
        return np.array([], dtype=int)
    inputs = list(table["runs"]["input"])
    return np.array([inputs.index(p) for p in table["reference"]["input"] if p in inputs], dtype=int)


def xi_el_of(xi, xi_error, rows):
    """Mean of the reference rows' ξ and its error (√Σσ²/n)."""
    if len(rows) == 0:
        return NAN, NAN
    return float(np.mean(xi[rows])), float(np.sqrt(np.sum(xi_error[rows] ** 2)) / len(rows))


def ratio_with_error(xi, xi_error, xi_el, xi_el_error):
    ratio = xi / xi_el
    return ratio, np.abs(ratio) * np.hypot(xi_error / xi, xi_el_error / xi_el)


def crossing(nu, xi, xi_error, xi_el, xi_el_error, threshold=1.25):
    """ν where ξ/ξ_el first crosses `threshold` upward in ν (lib/correlation/sweep.hpp's rule).
    Returns dict(nu_bc, nu_bc_error, status, nu_below, nu_above) with status 'bracketed',
    'all_above', 'all_below', 'too_few' or 'only_downward'."""
    nu, xi, xi_error = (np.asarray(a, dtype=float) for a in (nu, xi, xi_error))
    ok = np.isfinite(xi)
    nu, xi, xi_error = nu[ok], xi[ok], xi_error[ok]
    out = {"nu_bc": NAN, "nu_bc_error": NAN, "nu_below": NAN, "nu_above": NAN}
    # Runs at the same ν are merged: mean ξ, error √Σσ²/n.
    levels = np.unique(nu)
    xs = np.array([xi[nu == v].mean() for v in levels])
    es = np.array([np.sqrt(np.sum(xi_error[nu == v] ** 2)) / np.sum(nu == v) for v in levels])
    if len(levels) < 2:
        return dict(out, status="too_few")
    target = threshold * xi_el
    above = xs >= target
    for i in range(len(levels) - 1):
        if not above[i] and above[i + 1]:
            n1, n2, x1, x2 = levels[i], levels[i + 1], xs[i], xs[i + 1]
            nu_bc = n1 + (target - x1) * (n2 - n1) / (x2 - x1)
            # ∂ν/∂ξ1, ∂ν/∂ξ2, ∂ν/∂ξ_el of the linear interpolation.
            d1 = (n2 - n1) * (target - x2) / (x2 - x1) ** 2
            d2 = -(n2 - n1) * (target - x1) / (x2 - x1) ** 2
            del_ = threshold * (n2 - n1) / (x2 - x1)
            err = math.sqrt((d1 * es[i]) ** 2 + (d2 * es[i + 1]) ** 2 + (del_ * (xi_el_error or 0)) ** 2)
            return dict(out, nu_bc=float(nu_bc), nu_bc_error=err, nu_below=float(n1), nu_above=float(n2),
                        status="bracketed")
    if above.all():
        return dict(out, status="all_above")
    if not above.any():
        return dict(out, status="all_below")
    return dict(out, status="only_downward")


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
        jt = np.array([-b, a]) / (2 * a0 ** 2)
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


def analyse(table, k=2.0, factor=5, threshold=1.25, max_tail_share=0.05):
    """Everything the figures and the report need beyond the table itself. Runs whose tail
    share exceeds max_tail_share are not `measurable` and stay out of the ν_bc crossings."""
    xi, xi_err = magnitude_lengths(table, k, factor)
    cor = table["correlation"]
    tails = np.array([tail_share(cor["r"], cor["C"][i], cor["C_error"][i], k, factor) for i in range(len(xi))])
    measurable = np.isfinite(xi) & (tails <= max_tail_share)
    refs = reference_rows(table)
    xi_el, xi_el_err = xi_el_of(xi, xi_err, refs)
    ratio, ratio_err = ratio_with_error(xi, xi_err, xi_el, xi_el_err)
    runs = table["runs"]
    series = []
    for e, mu in sorted(set(zip(runs["restitution"].round(6), runs["friction"].round(6)))):
        rows = select(table, restitution=e, friction=mu)
        rows = rows[measurable[rows]]
        c = crossing(runs["packing_fraction"][rows], xi[rows], xi_err[rows], xi_el, xi_el_err, threshold)
        series.append(dict(c, restitution=float(e), friction=float(mu), runs=len(rows)))
    return {"xi": xi, "xi_error": xi_err, "tail_share": tails, "measurable": measurable,
            "max_tail_share": max_tail_share, "xi_el": xi_el, "xi_el_error": xi_el_err, "ratio": ratio,
            "ratio_error": ratio_err, "reference_rows": refs, "series": series, "threshold": threshold,
            "k": k, "factor": factor,
            "bin_width": float(table["correlation"]["attrs"]["bin_width"]) * factor}


def fmt_pm(value, error):
    """value ± error with the error's two significant digits (plain value if no error)."""
    if not np.isfinite(value):
        return "nan"
    if not (np.isfinite(error) and error > 0):
        return f"{value:.4g}"
    digits = max(0, 1 - int(math.floor(math.log10(error))))
    return f"{value:.{digits}f} ± {error:.{digits}f}"
