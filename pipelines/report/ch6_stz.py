"""Chapter 6, non-affine motion and the STZ law (thesis §6.3, Figs 6.9–6.11): d2min_maps.py's table
of the D²min maps, and gf-stz fit's coefficients, residuals and θ* against the incline's θ_c
(every number from the tables)."""
import math
import os

import numpy as np

from analysis import critical_angle as ca
from analysis import d2min_maps
from granflow import stz_table as stz
from report.render import head, quote


def percent(v):
    """A fraction in per cent, – when not finite."""
    return f"{100 * v:.1f} %" if math.isfinite(v) else "–"


def map_lines(table, maps_path):
    """Fig. 6.9: each map's black fraction and clusters at the default threshold and over the sweep."""
    maps, default, sweep, par = table["maps"], table["default"], table["sweep"], table["parameters"]
    threshold, t = default["threshold"], sweep["threshold"]
    lines = [
        "",
        "## Chapter 6: non-affine motion, D²min (thesis §6.3, Fig. 6.9)",
        "",
        f"Table `{maps_path}` from `pipelines/analysis/d2min_maps.py` over the gf-stz d2min maps "
        + ", ".join(f"({lab}) `{inp}`" for lab, inp in zip(maps["label"], table["runs"]["input"]))
        + f". Black: D²min per neighbour > {threshold:g} ⟨d⟩² (the sum over the neighbours within the "
        "cutoff divided by their number; the thesis gives no value); clusters: black grains whose "
        f"reference centres are closer than (R_i + R_j)(1 + {float(par['gap']):g}), Lees–Edwards minimum image. "
        f"Sweep: {len(t)} thresholds from {t.min():.3g} to {t.max():.3g} ⟨d⟩².",
        "",
        quote("d2min_clusters"),
        quote("d2min_locations"),
        *head("map", "strain", "grains (valid)", f"black at {threshold:g}", "clusters", "largest", "mean size",
              "cluster sizes (count × size)", "black over the sweep"),
    ]
    for k, label in enumerate(maps["label"]):
        hist = default["cluster_size_histogram"][k]
        sizes = ", ".join(f"{int(c)}×{s + 1}" for s, c in enumerate(hist) if c)
        frac = sweep["black_fraction"][k]
        lines.append(
            f"| ({label}) | {maps['start_strain'][k]:g} → {maps['end_strain'][k]:g} | {int(maps['grains'][k])} "
            f"({int(maps['valid_count'][k])}) | {percent(default['black_fraction'][k])} | "
            f"{int(default['cluster_count'][k])} | {int(default['largest_cluster'][k])} | "
            f"{stz.fmt(float(default['mean_cluster_size'][k]))} | {sizes or '–'} | "
            f"{percent(np.nanmin(frac))} – {percent(np.nanmax(frac))} |"
        )
    return lines


def overlap(default, sweep, p):
    """Pair p's Jaccard index and its chance value at the default threshold, and the ranges of J
    and of J/chance over the sweep (None where no value is finite)."""
    js, cs = sweep["jaccard"][p], sweep["jaccard_chance"][p]
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = js / cs
    finite, rfinite = np.isfinite(js), np.isfinite(ratio)
    return (
        float(default["jaccard"][p]),
        float(default["jaccard_chance"][p]),
        (np.min(js[finite]), np.max(js[finite])) if finite.any() else None,
        (np.min(ratio[rfinite]), np.max(ratio[rfinite])) if rfinite.any() else None,
    )


def overlap_lines(table):
    """The overlap of the maps' black sets against chance, per pair of maps."""
    default, sweep = table["default"], table["sweep"]
    lines = [
        "",
        "Overlap of the black sets, Jaccard index J = |A ∩ B|/|A ∪ B| over the grains valid in both, against "
        "the value of two independent random sets of the same fractions (chance):",
        "",
        *head("pair", f"J at {default['threshold']:g}", "chance", "J / chance", "J over the sweep",
              "J / chance over the sweep"),
    ]
    for p, pair in enumerate(default["pair"]):
        j, c, span, rspan = overlap(default, sweep, p)
        span = f"{span[0]:.3f} – {span[1]:.3f}" if span else "–"
        rspan = f"{rspan[0]:.2f} – {rspan[1]:.2f}" if rspan else "–"
        lines.append(
            f"| {pair} | {stz.fmt(j)} | {stz.fmt(c)} | {stz.fmt(j / c if c > 0 else math.nan)} | {span} | {rspan} |"
        )
    return lines


def d2min_section(maps_path):
    """Chapter 6, Fig. 6.9: black fractions, clusters and overlaps of the D²min maps
    (d2min_maps.py's table), at its default threshold and over its sweep."""
    table = d2min_maps.read_table(maps_path)
    return map_lines(table, maps_path) + overlap_lines(table)


def col(table, name):
    """A column of the fit rows."""
    return stz.column(table, name, "fit")


def jackknife(table, r):
    """θ*'s delete-one jackknife error in degrees (NaN in tables without the column)."""
    return col(table, "theta_star_jackknife_error")[r] if "theta_star_jackknife_error" in table["fit"] else math.nan


def fit_lines(table, fit_path, order):
    """The table, the laws and their fit, and each friction coefficient's coefficients."""
    fit, attrs = table["fit"], table["fit_attrs"]
    runs_kind = stz.kinds(table)
    pm = lambda n, r: stz.fmt_pm(col(table, n)[r], col(table, n + "_error")[r])  # noqa: E731
    lines = [
        "",
        "## Chapter 6: the STZ constitutive law (thesis §6.3, Figs 6.10–6.11)",
        "",
        f"Table `{fit_path}` (gf-stz fit): {len(runs_kind)} rows, {int(np.sum(runs_kind == 'shear'))} shear runs and "
        f"{int(np.sum(runs_kind == 'incline'))} incline bulk points. Eq. 6.36, x = γ̇⟨R⟩/√T = A[sinh(κμ) − "
        "cosh(κμ)/(ζμ)] with μ = s/p, fitted per friction coefficient on the shear runs at e = "
        f"{stz.fit_restitution(table):g} that are dense ({attrs.get('dense_rule', '?')}), objective "
        f"{attrs.get('objective', '?')}; tanθ* from eq. 6.35. μ(I) = μ_s + (μ₂ − μ_s)/(1 + I₀/I) fitted to the same "
        "points. rms: root-mean-square residual in s/p; “predicted”: the shear runs of that μ not fitted (other "
        "e, dilute), “incline”: the incline bulk points (never fitted).",
        "",
        quote("stz_fits"),
        quote("stz_incline"),
        *head("μ", "points", "A", "κ", "ζ", "tanθ*", "θ* (°)", "θ* jackknife error (°)", "χ²/dof", "μ_s", "μ₂", "I₀"),
    ]
    for r in order:
        dof = int(fit["dof"][r]) if "dof" in fit else 0
        chi = f"{col(table, 'chi2')[r]:.3g}/{dof}" if math.isfinite(col(table, "chi2")[r]) else "–"
        lines.append(
            f"| {col(table, 'friction')[r]:g} | {int(fit['points'][r]) if 'points' in fit else '–'} | {pm('A', r)} | "
            f"{pm('kappa', r)} | {pm('zeta', r)} | {pm('tan_theta_star', r)} | {pm('theta_star', r)} | "
            f"{stz.fmt(jackknife(table, r))} | {chi} | {pm('mu_s', r)} | {pm('mu_2', r)} | {pm('I0', r)} |"
        )
    return lines


def degenerate(table, order):
    """The friction coefficients (as written) whose A, κ or ζ has an error above 100 times its value."""
    return [
        f"{col(table, 'friction')[r]:g}"
        for r in order
        if any(not (abs(col(table, n + "_error")[r]) < 100 * abs(col(table, n)[r])) for n in ("A", "kappa", "zeta"))
    ]


def degenerate_lines(table, order):
    """What a fit whose coefficients are not determined one by one still fixes (none: no lines)."""
    found = degenerate(table, order)
    if not found:
        return []
    return [
        "",
        f"At μ = {', '.join(found)} A, κ and ζ are not determined one by one (an error above 100 times the "
        "value): the points lie near the κ → 0 limit of eq. 6.36, x ≈ c₁μ − c₂/μ (Aκ = c₁, A/ζ = c₂), which "
        "fixes tanθ* = √(c₂/c₁) but not the three coefficients; the delta-method error of θ* is then NaN and "
        "the jackknife error (refits without each point) stands.",
    ]


def better(a, b):
    """Which law has the smaller rms residual (– when one is not measured)."""
    if not (math.isfinite(a) and math.isfinite(b)):
        return "–"
    return "STZ" if a < b else "μ(I)" if b < a else "equal"


def rms_lines(table, order):
    """Each law's rms residual on the fitted, predicted and incline points, per μ."""
    fit = table["fit"]
    lines = [
        "",
        "rms residuals in s/p (count):",
        "",
        *head("μ", "STZ fitted", "μ(I) fitted", "better on the fitted points", "STZ predicted", "μ(I) predicted",
              "STZ incline", "μ(I) incline"),
    ]
    for r in order:
        a, b = col(table, "stz_rms")[r], col(table, "mu_of_I_rms")[r]
        pc = int(fit["predicted_count"][r]) if "predicted_count" in fit else 0
        ic = int(fit["incline_count"][r]) if "incline_count" in fit else 0
        lines.append(
            f"| {col(table, 'friction')[r]:g} | {stz.fmt(a)} | {stz.fmt(b)} | {better(a, b)} | "
            f"{stz.fmt(col(table, 'predicted_rms')[r])} ({pc}) | {stz.fmt(col(table, 'mu_of_I_predicted_rms')[r])} "
            f"({pc}) | {stz.fmt(col(table, 'incline_rms')[r])} ({ic}) | "
            f"{stz.fmt(col(table, 'mu_of_I_incline_rms')[r])} ({ic}) |"
        )
    return lines


def predicted_split(table, r):
    """The predicted (not fitted) shear runs of fit row r's μ, dense then dilute: for each, the rms
    residual and the count of each law's residuals."""
    runs_kind, rcol = stz.kinds(table), lambda n: stz.column(table, n)  # noqa: E731
    dense_flag = np.asarray(table["runs"]["dense"]).astype(bool)
    fitted_flag = np.asarray(table["runs"]["fitted"]).astype(bool)
    mine = (runs_kind == "shear") & stz.same(rcol("friction"), col(table, "friction")[r]) & ~fitted_flag
    out = []
    for which in (dense_flag, ~dense_flag):
        for name in ("residual", "residual_mu_of_I"):
            values = rcol(name)[mine & which]
            out.append((stz.rms(values), int(np.sum(np.isfinite(values)))))
    return out


def predicted_lines(table, order):
    """The predicted shear runs split by the dense rule: the thesis claims the dense ones only."""
    lines = [
        "",
        "The predicted shear runs (not fitted) split by the dense rule, rms residual in s/p (count):",
        "",
        *head("μ", "STZ, dense", "μ(I), dense", "STZ, dilute", "μ(I), dilute"),
    ]
    for r in order:
        cells = [f"{stz.fmt(rms)} ({count})" for rms, count in predicted_split(table, r)]
        lines.append(f"| {col(table, 'friction')[r]:g} | " + " | ".join(cells) + " |")
    return lines


def incline_lines(table):
    """The incline bulk points against the shear fit of their μ (none: no lines)."""
    incline = np.flatnonzero(stz.kinds(table) == "incline")
    if not len(incline):
        return []
    get = lambda n: stz.column(table, n)  # noqa: E731
    lines = [
        "",
        "Incline bulk points against the shear fit of their μ:",
        "",
        *head("input", "μ", "e", "γ̇⟨R⟩/√T", "s/p", "STZ", "residual", "μ(I) residual"),
    ]
    for r in incline:
        lines.append(
            f"| `{os.path.basename(str(table['runs']['input'][r]))}` | {get('friction')[r]:g} | "
            f"{get('restitution')[r]:g} | {stz.fmt_pm(get('rate_R_over_sqrt_T')[r], get('rate_R_over_sqrt_T_error')[r])} "
            f"| {stz.fmt_pm(get('s_over_p')[r], get('s_over_p_error')[r])} | {stz.fmt(get('prediction')[r])} | "
            f"{stz.fmt(get('residual')[r])} | {stz.fmt(get('residual_mu_of_I')[r])} |"
        )
    return lines


def theta_star(table, row):
    """θ* of a fit row and its error: the delta method's, or the jackknife's where that is NaN."""
    ts, tse = col(table, "theta_star")[row], col(table, "theta_star_error")[row]
    return ts, tse if math.isfinite(tse) else jackknife(table, row)


def repose_lines(table, critical_path):
    """θ* of the critical-angle sweep's μ against its θ_c."""
    crit = ca.read_table(critical_path)
    res, cr = crit["critical_angle"], crit["runs"]
    theta_c, half = float(res["theta_c"]), float(res["half_width"])
    e_c = float(cr["restitution"][0]) if len(cr["restitution"]) else math.nan
    mu_c = float(cr["friction"][0]) if len(cr["friction"]) else math.nan
    row = stz.fit_row(table, mu_c) if math.isfinite(mu_c) else None
    lines = ["", quote("repose_angle")]
    if row is None or not math.isfinite(theta_c):
        return lines + [
            f"θ* against the incline's critical angle: not compared (θ_c = {stz.fmt(theta_c)}°, μ = {stz.fmt(mu_c)}: "
            "no fit of that μ or no θ_c)."
        ]
    ts, tse = theta_star(table, row)
    e_fit = stz.fit_restitution(table)
    note = "" if abs(e_c - e_fit) < 1e-9 else f" Note: the critical-angle sweep is at e = {e_c:g}, the fit at e = {e_fit:g}."
    return lines + [
        f"θ* (μ = {mu_c:g}) = {stz.fmt_pm(ts, tse)}° against the incline's critical angle θ_c = {theta_c:g}° ± "
        f"{half:g}° (`{critical_path}`, bracket ({float(res['theta_below']):g}°, {float(res['theta_above']):g}°]): "
        f"difference {stz.fmt(ts - theta_c)}°.{note}"
    ]


def stz_section(fit_path, critical_path=None):
    """Chapter 6, the STZ law (thesis §6.3, Figs 6.10, 6.11): gf-stz fit's coefficients per μ, θ*
    against the incline's θ_c, the rms residuals of the fitted and predicted points, and the STZ law
    against μ(I) (every number from the table)."""
    table = stz.read_table(fit_path)
    order = np.argsort(col(table, "friction"))
    lines = (
        fit_lines(table, fit_path, order)
        + degenerate_lines(table, order)
        + rms_lines(table, order)
        + predicted_lines(table, order)
        + incline_lines(table)
    )
    return lines + (repose_lines(table, critical_path) if critical_path else [])
