"""Chapter 4, incline flow (thesis §4.3–4.4, Figs 4.7–4.10): incline_bulk.py's and
critical_angle.py's tables, the bulk rheology, momentum balance, V_x exponent and θ_c, and the
comparison with simple shear at the same ν."""
import math

import numpy as np

from analysis import critical_angle as ca
from analysis import incline_bulk as ib
from analysis import steady_state as ss
from report.render import fmt, head, quote, sigmas, subsection

# The bulk invariants beside simple shear's: (incline column, shear column, label).
INVARIANTS = (
    ("s_over_p", "s_over_p", "s/p"),
    ("inertial", "rate_R_over_sqrt_T", "γ̇⟨R⟩/√T"),
    ("mT_over_pR2", "mT_over_pR2", "mT/(p⟨R⟩²)"),
)


def interpolate_shear(sweep, friction, restitution, name, nu):
    """(value, error) of a shear steady quantity linearly interpolated in ν at the given μ and e;
    None outside the sweep's ν range."""
    rows = ss.select(sweep, friction=friction, restitution=restitution)
    x = sweep["runs"]["packing_fraction"][rows]
    if len(rows) < 2 or not x[0] <= nu <= x[-1]:
        return None
    k = min(int(np.searchsorted(x, nu, side="right")) - 1, len(x) - 2)
    w = (nu - x[k]) / (x[k + 1] - x[k])
    v, e = sweep["steady"][name][rows], sweep["steady"][name + "_error"][rows]
    return (1 - w) * v[k] + w * v[k + 1], math.hypot((1 - w) * e[k], w * e[k + 1])


def bulk_lines(inc, incline_path, order):
    """The table, how its bulk is chosen, and each run's bulk rheology and momentum balance."""
    runs, bulk, bal = inc["runs"], inc["bulk"], inc["balance"]
    d = 2 * runs["mean_radius"]
    lines = [
        "",
        "## Chapter 4: incline flow (thesis §4.3–4.4, Figs 4.7–4.10)",
        "",
        f"Table `{incline_path}` from `pipelines/analysis/incline_bulk.py`: {runs['grains'][0]} mobile grains "
        f"on a base {runs['layer_length'][0] / d[0]:.1f} mean diameters long, e = {runs['restitution'][0]:g}; "
        "profiles averaged over x and over the part of each run given by “from” (gf-incline, `/profiles`). "
        f"Bulk = layers ≥ {float(inc['parameters']['base_skip']):g} diameters above the base and ≥ "
        f"{float(inc['parameters']['surface_skip']):g} below the surface H = Σm/(L_x ν_bulk); ± is the "
        "scatter of the bulk layers (standard error of their mean), drift the relative change across the "
        "bulk (straight-line fit). “steady” is gf-incline's check (flow rate and kinetic energy: first and "
        "second half of the averaged part agree within 3σ).",
        "",
        quote("incline_bulk_profiles"),
        quote("incline_invariants"),
        *head("θ", "μ", "steady", "from (τ)", "run (τ)", "H/σ", "bulk layers", "ν", "s/p (tan θ)", "γ̇⟨R⟩/√T",
              "mT/(p⟨R⟩²)", "drift s/p, γ̇⟨R⟩/√T, mT/p⟨R⟩²", "max dev. Σyy, s from g cos θ W, g sin θ W"),
    ]
    for r in order:
        if not runs["flowing"][r]:
            lines.append(
                f"| {runs['angle'][r]:g} | {runs['friction'][r]:g} | {runs['steady'][r]} | "
                f"{runs['steady_from_tau'][r]:.0f} | {runs['time'][r]:.0f} | – | – | "
                f"{bulk['packing_fraction'][r]:.3f} | not flowing | | | | |"
            )
            continue
        cells = [
            fmt(bulk[n][r], bulk[n + "_error"][r]) for n in ("packing_fraction", "s_over_p", "inertial", "mT_over_pR2")
        ]
        cells[1] += f" ({math.tan(math.radians(runs['angle'][r])):.4f})"
        lines.append(
            f"| {runs['angle'][r]:g} | {runs['friction'][r]:g} | {runs['steady'][r]} | "
            f"{runs['steady_from_tau'][r]:.0f} | {runs['time'][r]:.0f} | "
            f"{runs['surface_height'][r] / d[r]:.1f} | {runs['bulk_layers'][r]} | "
            + " | ".join(cells)
            + f" | {bulk['s_over_p_drift'][r]:+.3f}, {bulk['inertial_drift'][r]:+.3f}, "
            f"{bulk['mT_over_pR2_drift'][r]:+.3f} | {bal['yy_max_deviation'][r]:.2%}, "
            f"{bal['xy_max_deviation'][r]:.2%} |"
        )
    return lines


def branched_lines(runs, order):
    """Which runs started from another run's state (none: no lines)."""
    branched = [r for r in order if "start_friction" in runs and np.isfinite(runs["start_friction"][r])]
    if not branched:
        return []
    return [
        "",
        "Branched runs (“from” and “run” count from the branch point; velocities kept): "
        + "; ".join(
            f"θ = {runs['angle'][r]:g}°, μ = {runs['friction'][r]:g} from `{runs['start'][r]}` (μ = "
            f"{runs['start_friction'][r]:g}) at its {runs['start_time'][r]:.0f} τ"
            for r in branched
        )
        + ".",
    ]


def worst_balance(inc, flowing):
    """The largest deviation from the momentum balance over the bulk layers of the flowing runs."""
    bal = inc["balance"]
    return max(float(np.max(bal["yy_max_deviation"][flowing])), float(np.max(bal["xy_max_deviation"][flowing])))


def profile_lines(inc, flowing):
    """The momentum balance and the fits to the steady V_x(y) of the flowing runs."""
    runs, fit = inc["runs"], inc["fit"]
    lines = [
        "",
        f"Momentum balance (eq. 4.7–4.9, must hold whatever the rheology): largest deviation over "
        f"the bulk layers of all flowing runs {worst_balance(inc, flowing):.2%} (issue 4 asks ≤ 3 %).",
        "",
        "### V_x profile",
        "",
        "Fits to the steady V_x(y): the Bagnold form V_x = V_s − c (H − y)^a (depth below the "
        "surface; a = 3/2 is the thesis' y^{3/2}) on the bulk layers and on all layers from the base "
        "skip to the surface, and a plain power law V_x ∝ y^b on the bulk layers:",
        "",
        *head("θ", "μ", "a (bulk)", "a (to the surface)", "V_s/√(g⟨R⟩)", "b of y^b"),
    ]
    for r in flowing:
        lines.append(
            f"| {runs['angle'][r]:g} | {runs['friction'][r]:g} | {fit['velocity_exponent'][r]:.2f} | "
            f"{fit['velocity_exponent_full'][r]:.2f} | {fit['surface_velocity'][r]:.3g} | "
            f"{fit['power_law_exponent'][r]:.2f} |"
        )
    return lines


def shear_comparison(inc, sweep, flowing):
    """Fig 4.10's check: per flowing run and invariant, (row, label, incline value, its error,
    shear's (value, error) interpolated at the run's bulk ν, or None outside the sweep)."""
    runs, bulk = inc["runs"], inc["bulk"]
    out = []
    for r in flowing:
        for name, shear_name, label in INVARIANTS:
            got = interpolate_shear(
                sweep, runs["friction"][r], runs["restitution"][r], shear_name, bulk["packing_fraction"][r]
            )
            out.append((r, label, bulk[name][r], bulk[name + "_error"][r], got))
    return out


def comparison_lines(inc, sweep, sweep_path, flowing):
    """Fig 4.10: the bulk invariants against simple shear's at the same ν."""
    runs, bulk = inc["runs"], inc["bulk"]
    lines = [
        *subsection("Incline bulk against simple shear at the same ν (Fig 4.10)", "shear_incline_match"),
        f"Shear values from `{sweep_path}` at the same μ and e, linearly interpolated in ν between the "
        "sweep's packing fractions (– when the incline's ν is outside them); difference in units of the "
        "combined error (incline: bulk-layer scatter; shear: blocking).",
        "",
        *head("θ", "μ", "ν", "invariant", "incline", "shear at ν", "(incline − shear)/σ", "relative"),
    ]
    for r, label, a, ea, got in shear_comparison(inc, sweep, flowing):
        where = f"| {runs['angle'][r]:g} | {runs['friction'][r]:g} | {bulk['packing_fraction'][r]:.3f}"
        if got is None:
            lines.append(f"{where} | {label} | {fmt(a, ea)} | – | – | – |")
            continue
        b, eb = got
        lines.append(f"{where} | {label} | {fmt(a, ea)} | {fmt(b, eb)} | {sigmas(a - b, ea, eb)} | {(a - b) / b:+.1%} |")
    return lines


def critical_lines(crit, critical_path):
    """§4.3.1: each angle's mean flow rate and state, and θ_c where the sweep brackets it."""
    cr, res = crit["runs"], crit["critical_angle"]
    below, above = float(res["theta_below"]), float(res["theta_above"])
    lines = [
        *subsection("Critical angle θ_c (§4.3.1)", "critical_angle"),
        f"Table `{critical_path}` from `pipelines/analysis/critical_angle.py`: mean flow rate V̄ over the "
        f"last {float(crit['parameters']['window']):g} τ of each run (blocking error), change Δ between "
        f"that window's halves; rest = |V̄| ≤ max(3σ, {float(crit['parameters']['rest_velocity']):g}), "
        f"steady = |Δ| ≤ max(3σ_Δ, {float(crit['parameters']['drift']):g}·V̄).",
        "",
        *head("θ", "μ", "V̄/√(g⟨R⟩)", "Δ/√(g⟨R⟩)", "state"),
    ]
    for k in range(len(cr["angle"])):
        lines.append(
            f"| {cr['angle'][k]:g} | {cr['friction'][k]:g} | "
            f"{fmt(cr['mean_velocity'][k], cr['mean_velocity_error'][k])} | "
            f"{fmt(cr['drift'][k], cr['drift_error'][k])} | {cr['state'][k]} |"
        )
    if math.isfinite(below) and math.isfinite(above):
        lines += [
            "",
            f"**θ_c = {float(res['theta_c']):g}° ± {float(res['half_width']):g}°**: the lowest angle of "
            f"steady flow lies in ({below:g}°, {above:g}°]"
            + ("." if int(res["consistent"]) else "; the sweep is not monotonic (a lower angle flows)"),
        ]
    else:
        lines += ["", f"θ_c not bracketed by this sweep: in ({below:g}°, {above:g}°]."]
    return lines


def section(incline_path, critical_path, sweep_path):
    """Chapter 4, incline flow, beside thesis §4.3–4.4 (the comparison with shear only with a sweep)."""
    inc, crit = ib.read_table(incline_path), ca.read_table(critical_path)
    runs = inc["runs"]
    order = np.lexsort((runs["angle"], runs["friction"]))
    flowing = order[runs["flowing"][order] == 1]
    lines = bulk_lines(inc, incline_path, order) + branched_lines(runs, order)
    if len(flowing):
        lines += profile_lines(inc, flowing)
    if sweep_path:
        lines += comparison_lines(inc, ss.read_table(sweep_path), sweep_path, flowing)
    return lines + critical_lines(crit, critical_path)
