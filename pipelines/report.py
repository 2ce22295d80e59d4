#!/usr/bin/env python3
"""report.py --size SIZE --output REPORT.md [chapter options] PACKING.h5...: the reproduction
summary, our numbers beside the thesis' where it gives them. Each chapter adds its section."""
import argparse
import math
import os

import h5py
import numpy as np

from analysis import critical_angle as ca
from analysis import d2min_maps
from analysis import incline_bulk as ib
from analysis import jamming_point
from analysis import steady_state as ss
from granflow import correlation_table as ct
from granflow import kinetic_table as kt
from granflow import network_table as nt
from granflow import stz_table as stz
from granflow import outputs
from granflow.outputs import write_text


def packing_rows(paths):
    rows = []
    for path in paths:
        with h5py.File(path, "r") as f:
            a = f["/parameters"].attrs
            obs = f["/observables"]
            rows.append(
                (
                    os.path.basename(path),
                    len(f["/particles/grains/radius"]),
                    float(a["packing-fraction"]),
                    float(obs["packing_fraction/value"][0]),
                    float(obs["max_overlap/value"][0]) / float(a["mean-diameter"]),
                    int(a["seed"]),
                )
            )
    return rows


def fmt(value, error=None, plateau=1):
    """value ± error to the error's precision; † marks an error that is only a lower bound."""
    if error is None or not error > 0:
        return f"{value:.4g}"
    last = math.floor(math.log10(error)) - 1  # the error's second significant digit
    lead = math.floor(math.log10(max(abs(value), error)))
    if -3 <= lead < 5:
        d = max(0, -last)
        text = f"{value:.{d}f} ± {error:.{d}f}"
    else:
        d = max(0, lead - last)
        text = f"({value / 10 ** lead:.{d}f} ± {error / 10 ** lead:.{d}f})e{lead}"
    return text + ("" if plateau else " †")


def cell(table, name, row):
    st = table["steady"]
    return fmt(st[name][row], st[name + "_error"][row], st[name + "_plateau"][row]) + unsteady_mark(table, row)


def unsteady_mark(table, row):
    """‡ for a run whose steady part failed the stationarity check of steady_state.py."""
    stationary = table["runs"].get("stationary")
    return " ‡" if stationary is not None and not stationary[row] else ""


def steady_start_note(table):
    """How the steady parts of a steady_state.py table were chosen, and which were not stationary."""
    runs, prm = table["runs"], table["parameters"]
    from_strain = float(prm["from_strain"])
    if "steady_from" not in runs:
        return f"steady values average the recorded rows with strain ≥ {from_strain:g}."
    start, strain = runs["steady_from"], runs["strain"]
    late = [i for i in range(len(start)) if start[i] > from_strain + 1e-9]
    text = (
        f"steady values average the recorded rows from the start of each run's steady part: strain "
        f"{from_strain:g}"
        + (
            ", or later where MSER on the block means of T and p finds the run's transient "
            "longer (at most half of the run)"
            if int(prm.get("detect_transient", 0))
            else ""
        )
        + f". Runs last strain {strain.min():g}–{strain.max():g}; {len(late)} of {len(start)} start later than "
        f"{from_strain:g} (up to {start.max():.3g}). Error bars are those of each run's time average (blocking): "
        "they leave out the spread between packings at the same ν, which in dilute flows can be several times "
        "larger (docs/results/chapter4.md, “Paper size”)."
    )
    if "stationary" in runs:
        bad = [i for i in range(len(start)) if not runs["stationary"][i]]
        text += (
            f" ‡ marks a run whose steady part is not stationary (the means of T or p over its halves differ by "
            f"more than {ss.STATIONARY_SIGMAS} blocking errors): {len(bad)} of {len(start)}"
        )
        text += (
            " (" + ", ".join(f"`{os.path.basename(runs['input'][i])}` {runs['halves_z'][i]:.1f}σ" for i in bad) + ")."
            if bad
            else "."
        )
    return text


def sigmas(difference, *errors):
    """A difference in units of its combined standard error."""
    sigma = math.hypot(*errors)
    if sigma == 0:
        return "0" if difference == 0 else "∞"
    return f"{difference / sigma:+.1f}".replace("-0.0", "+0.0")


def quote(text, line):
    """A thesis sentence as its own Markdown block quote."""
    return f"> “{text}” (thesis l. {line})\n"


def ch4_section(sweep_path, bagnold_path, reference_path):
    """Chapter 4: steady simple shear beside the statements of thesis §4.2.2."""
    sweep, bagnold = ss.read_table(sweep_path), ss.read_table(bagnold_path)
    runs, st = sweep["runs"], sweep["steady"]
    from_strain = float(sweep["parameters"]["from_strain"])
    diameter = 2 * runs["mean_radius"]
    overlap = sweep["diagnostics"]["max_overlap_max"] / diameter
    worst = int(np.argmax(overlap))
    lines = [
        "",
        "## Chapter 4: simple shear (thesis §4.2.2, Figs 4.1–4.6)",
        "",
        f"Tables `{sweep_path}` (ν × e sweep) and `{bagnold_path}` (Fig 4.2), from "
        f"`pipelines/analysis/steady_state.py`: N = {runs['grains'][0]}, "
        f"strain step γ̇dt = {runs['strain_step'][0]:g}; {steady_start_note(sweep)} "
        f"± is the {sweep['parameters']['error_method']}; † marks an error that is only "
        "a lower bound (no blocking plateau: the run is short for its correlation time). "
        f"Largest overlap in the steady parts: {overlap[worst]:.2e} "
        f"mean diameters (`{os.path.basename(runs['input'][worst])}`); mean solver iterations per step "
        f"{sweep['diagnostics']['solver_iterations_mean'].min():.3g}–"
        f"{sweep['diagnostics']['solver_iterations_mean'].max():.3g}.",
        "",
    ]

    # Fig 4.2: Bagnold scaling.
    rows = np.argsort(bagnold["runs"]["rate"])
    lines += [
        "### Bagnold scaling (Fig 4.2)",
        "",
        quote(
            "Although the shear rates in the plots differ by a factor of 10^4, the normalized pressure "
            "is virtually identical for both systems.",
            "362–369",
        ),
        quote(
            "The invariance in Newton's equations also predicts that sγ̇⁻² and Tγ̇⁻² are independent "
            "of γ̇. For all of the simulations we have carried out these predictions from the invariance "
            "are upheld",
            "371",
        ),
        f"Ours, ν = {bagnold['runs']['packing_fraction'][rows[0]]:.3f}, e = "
        f"{bagnold['runs']['restitution'][rows[0]]:g}, μ = {bagnold['runs']['friction'][rows[0]]:g}, "
        "same packing and strain step (dt ∝ 1/γ̇):",
        "",
        "| quantity | " + " | ".join(f"γ̇ = {r:g}" for r in bagnold["runs"]["rate"][rows]) + " | (last − first)/σ |",
        "|---|" + "---|" * len(rows) + "---|",
    ]
    bst = bagnold["steady"]
    for name, label in (
        ("pressure_scaled", "p/(γ̇²m)"),
        ("shear_stress_scaled", "s/(γ̇²m)"),
        ("temperature_scaled", "T/(γ̇²⟨R⟩²)"),
    ):
        a, b = rows[0], rows[-1]
        lines.append(
            f"| {label} | "
            + " | ".join(cell(bagnold, name, r) for r in rows)
            + f" | {sigmas(bst[name][b] - bst[name][a], bst[name + '_error'][a], bst[name + '_error'][b])} |"
        )

    # Fig 4.3: transient and fluctuations of the invariants, from where the tables start the run.
    run = ss.read_run(reference_path)
    from_strain = ss.steady_start(run, from_strain, int(bagnold["parameters"].get("detect_transient", 0)))
    end = float(run["series"]["strain"][-1])
    middle = 0.5 * (from_strain + end)
    first, second = ss.steady_values(run, from_strain, middle)[0], ss.steady_values(run, middle)[0]
    inst = ss.invariant_series(run)
    steady = run["series"]["strain"] >= from_strain
    lines += [
        "",
        "### Steady state and fluctuations (Fig 4.3)",
        "",
        quote("For all quantities, steady flow is reached by a shear of approximately 0.5", "377"),
        quote("the values of s/p and mT/p⟨R⟩² fluctuate much more than γ̇⟨R⟩/√T", "377"),
        f"Ours (`{os.path.basename(reference_path)}`): the steady part split in two halves — equal means "
        "(|difference| of a few σ at most) say the transient is over by strain "
        f"{from_strain:g}; relative fluctuation = standard deviation / mean of the per-step values.",
        "",
        f"| invariant | strain {from_strain:g}–{middle:.3g} | {middle:.3g}–{end:.3g} | difference/σ "
        "| relative fluctuation |",
        "|---|---|---|---|---|",
    ]
    for name, label in (("s_over_p", "s/p"), ("rate_R_over_sqrt_T", "γ̇⟨R⟩/√T"), ("mT_over_pR2", "mT/(p⟨R⟩²)")):
        (a, ea, pa), (b, eb, pb) = first[name], second[name]
        x = inst[name][steady]
        lines.append(
            f"| {label} | {fmt(a, ea, pa)} | {fmt(b, eb, pb)} | {sigmas(b - a, ea, eb)} "
            f"| {np.nanstd(x) / abs(np.nanmean(x)):.3g} |"
        )

    # Figs 4.4 and 4.5: e = 0, μ = 0 against ν.
    zero = ss.select(sweep, restitution=0.0, friction=0.0)
    lines += [
        "",
        "### Steady rheology against ν, e = 0, μ = 0 (Figs 4.4, 4.5)",
        "",
        quote(
            "for packing fractions larger than 0.75 there is a large increase in the values of the stresses "
            "and granular temperature",
            "384",
        ),
        quote("Both the shear stress and pressure are seen to diverge at a finite packing fraction", "386"),
        quote("Previous research [71, 27] has shown that N_1 ∼ 10^-2.", "358"),
        quote("We see that the static part of the pressure becomes larger than the kinetic part for ν > 0.4.", "404"),
        "| ν | steady from | p/(γ̇²m) | s/(γ̇²m) | T/(γ̇²⟨R⟩²) | s/p | N₁ | pˢ/(γ̇²m) | pᵏ/(γ̇²m) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in zero:
        start = f"{runs['steady_from'][r]:.3g} of {runs['strain'][r]:g}" if "steady_from" in runs else "–"
        lines.append(
            f"| {runs['packing_fraction'][r]:.3f} | {start} | "
            + " | ".join(
                cell(sweep, name, r)
                for name in (
                    "pressure_scaled",
                    "shear_stress_scaled",
                    "temperature_scaled",
                    "s_over_p",
                    "normal_stress_difference",
                    "pressure_static_scaled",
                    "pressure_kinetic_scaled",
                )
            )
            + " |"
        )
    n1 = np.abs(st["normal_stress_difference"][ss.select(sweep, friction=0.0)])
    static_wins = [runs["packing_fraction"][r] for r in zero if st["pressure_static"][r] > st["pressure_kinetic"][r]]
    kinetic_wins = [runs["packing_fraction"][r] for r in zero if st["pressure_static"][r] <= st["pressure_kinetic"][r]]
    lines += [
        "",
        f"Ours: |N₁| = {n1.min():.2g}–{n1.max():.2g} over all {len(n1)} μ = 0 runs of the sweep (every e). "
        f"pˢ > pᵏ at ν = {', '.join(f'{v:.3f}' for v in static_wins) or 'none'}; "
        f"pˢ ≤ pᵏ at ν = {', '.join(f'{v:.3f}' for v in kinetic_wins) or 'none'}.",
    ]

    # Fig 4.6: static pressure against ν for every e.
    frictionless = ss.select(sweep, friction=0.0)
    es = np.unique(runs["restitution"][frictionless])
    lines += [
        "",
        "### Static pressure for several e, μ = 0 (Fig 4.6)",
        "",
        quote("For large packing fractions the pressures become independent of e.", "408"),
        quote(
            "At low values of packing fraction the dynamics becomes less linked to geometric constraints and "
            "there is a large variance with e.",
            "408",
        ),
        "| ν | " + " | ".join(f"pˢ/(γ̇²m), e = {e:g}" for e in es) + " | max/min over e |",
        "|---|" + "---|" * len(es) + "---|",
    ]
    for nu in np.unique(runs["packing_fraction"][frictionless]):
        cells, values = [], []
        for e in es:
            r = ss.select(sweep, friction=0.0, restitution=e, packing_fraction=nu)
            cells.append(cell(sweep, "pressure_static_scaled", r[0]) if len(r) else "–")
            values += [st["pressure_static_scaled"][r[0]]] if len(r) else []
        ratio = f"{max(values) / min(values):.3g}" if len(values) > 1 else "–"
        lines.append(f"| {nu:.3f} | " + " | ".join(cells) + f" | {ratio} |")
    return lines


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


def incline_section(incline_path, critical_path, sweep_path):
    """Chapter 4, incline flow: bulk rheology, momentum balance, V_x exponent, θ_c, and the
    comparison with simple shear at the same ν (thesis §4.3–4.4)."""
    inc, crit = ib.read_table(incline_path), ca.read_table(critical_path)
    runs, bulk, bal, fit = inc["runs"], inc["bulk"], inc["balance"], inc["fit"]
    order = np.lexsort((runs["angle"], runs["friction"]))
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
        quote(
            "In the bulk of the flow, where the boundaries do not play a role, the packing fraction is "
            "constant and the granular temperature is linear. The y-dependence of the average flow "
            "velocity is very close to y^{3/2}",
            "449",
        ),
        quote("These three invariant quantities should only depend on the packing fraction and *not* on y.", "461"),
        "| θ | μ | steady | from (τ) | run (τ) | H/σ | bulk layers | ν | s/p (tan θ) | γ̇⟨R⟩/√T | "
        "mT/(p⟨R⟩²) | drift s/p, γ̇⟨R⟩/√T, mT/p⟨R⟩² | max dev. Σyy, s from g cos θ W, g sin θ W |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
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
    branched = [r for r in order if "start_friction" in runs and np.isfinite(runs["start_friction"][r])]
    if branched:
        lines += [
            "",
            "Branched runs (“from” and “run” count from the branch point; velocities kept): "
            + "; ".join(
                f"θ = {runs['angle'][r]:g}°, μ = {runs['friction'][r]:g} from `{runs['start'][r]}` (μ = "
                f"{runs['start_friction'][r]:g}) at its {runs['start_time'][r]:.0f} τ"
                for r in branched
            )
            + ".",
        ]
    flowing = order[runs["flowing"][order] == 1]
    if len(flowing):
        worst = max(float(np.max(bal["yy_max_deviation"][flowing])), float(np.max(bal["xy_max_deviation"][flowing])))
        lines += [
            "",
            f"Momentum balance (eq. 4.7–4.9, must hold whatever the rheology): largest deviation over "
            f"the bulk layers of all flowing runs {worst:.2%} (issue 4 asks ≤ 3 %).",
            "",
            "### V_x profile",
            "",
            "Fits to the steady V_x(y): the Bagnold form V_x = V_s − c (H − y)^a (depth below the "
            "surface; a = 3/2 is the thesis' y^{3/2}) on the bulk layers and on all layers from the base "
            "skip to the surface, and a plain power law V_x ∝ y^b on the bulk layers:",
            "",
            "| θ | μ | a (bulk) | a (to the surface) | V_s/√(g⟨R⟩) | b of y^b |",
            "|---|---|---|---|---|---|",
        ]
        for r in flowing:
            lines.append(
                f"| {runs['angle'][r]:g} | {runs['friction'][r]:g} | {fit['velocity_exponent'][r]:.2f} | "
                f"{fit['velocity_exponent_full'][r]:.2f} | {fit['surface_velocity'][r]:.3g} | "
                f"{fit['power_law_exponent'][r]:.2f} |"
            )
    if sweep_path:
        sweep = ss.read_table(sweep_path)
        lines += [
            "",
            "### Incline bulk against simple shear at the same ν (Fig 4.10)",
            "",
            quote(
                "Data from simple shear flow (circles) and flow down an incline (squares) match on the same "
                "curves for both cases.",
                "489",
            ),
            f"Shear values from `{sweep_path}` at the same μ and e, linearly interpolated in ν between the "
            "sweep's packing fractions (– when the incline's ν is outside them); difference in units of the "
            "combined error (incline: bulk-layer scatter; shear: blocking).",
            "",
            "| θ | μ | ν | invariant | incline | shear at ν | (incline − shear)/σ | relative |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for r in flowing:
            for name, shear_name, label in (
                ("s_over_p", "s_over_p", "s/p"),
                ("inertial", "rate_R_over_sqrt_T", "γ̇⟨R⟩/√T"),
                ("mT_over_pR2", "mT_over_pR2", "mT/(p⟨R⟩²)"),
            ):
                got = interpolate_shear(
                    sweep, runs["friction"][r], runs["restitution"][r], shear_name, bulk["packing_fraction"][r]
                )
                a, ea = bulk[name][r], bulk[name + "_error"][r]
                if got is None:
                    lines.append(
                        f"| {runs['angle'][r]:g} | {runs['friction'][r]:g} | "
                        f"{bulk['packing_fraction'][r]:.3f} | {label} | {fmt(a, ea)} | – | – | – |"
                    )
                    continue
                b, eb = got
                lines.append(
                    f"| {runs['angle'][r]:g} | {runs['friction'][r]:g} | {bulk['packing_fraction'][r]:.3f}"
                    f" | {label} | {fmt(a, ea)} | {fmt(b, eb)} | {sigmas(a - b, ea, eb)} | "
                    f"{(a - b) / b:+.1%} |"
                )
    cr, res = crit["runs"], crit["critical_angle"]
    below, above = float(res["theta_below"]), float(res["theta_above"])
    lines += [
        "",
        "### Critical angle θ_c (§4.3.1)",
        "",
        quote(
            "We identify the critical angle θ_c by the angle below which the average velocity fluctuates "
            "around zero.",
            "434",
        ),
        f"Table `{critical_path}` from `pipelines/analysis/critical_angle.py`: mean flow rate V̄ over the "
        f"last {float(crit['parameters']['window']):g} τ of each run (blocking error), change Δ between "
        f"that window's halves; rest = |V̄| ≤ max(3σ, {float(crit['parameters']['rest_velocity']):g}), "
        f"steady = |Δ| ≤ max(3σ_Δ, {float(crit['parameters']['drift']):g}·V̄).",
        "",
        "| θ | μ | V̄/√(g⟨R⟩) | Δ/√(g⟨R⟩) | state |",
        "|---|---|---|---|---|",
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


def ch5_section(correlate_path, clusters_path):
    """Chapter 5: force correlations, P(f) and ν_bc beside the statements of thesis ch. 5."""
    table = ct.read_table(correlate_path)
    res = ct.analyse(table)
    runs, cor, fo = table["runs"], table["correlation"], table["forces"]
    sigma = ct.mean_diameter(table)
    thr = res["threshold"]
    lines = [
        "",
        "## Chapter 5: microstructure (thesis §5.1–5.3, Figs 5.1–5.10)",
        "",
        f"Table `{correlate_path}` (gf-correlate, one row per run): N = {int(runs['grains'][0])}, "
        f"{int(runs['frames'].min())}–{int(runs['frames'].max())} frames per run at strain ≥ "
        f"{float(cor['attrs']['from_strain']):g}"
        + (
            f" or past the run's transient (MSER on T and p; first frames at strain "
            f"{float(np.min(runs['first_strain'])):.3g}–{float(np.max(runs['first_strain'])):.3g})"
            if int(cor["attrs"].get("detect_transient", 0))
            else ""
        )
        + f", largest lag {float(cor['attrs']['max_lag']) / sigma:.1f}σ "
        f"(σ = {sigma:.4g} the mean diameter). ξ below is gf-correlate's ξ_|C| (`/correlation/xi_abs`: "
        f"eq. 5.2 on |C̄| in bins of {res['bin_width'] / sigma:.2f}σ, {res['threshold_kind']}-thresholded at "
        f"{res['k']:g} jackknife errors, block-jackknife errors; `lib/correlation/decay_length.hpp`); "
        "gf-correlate's eq.-5.2 ξ on the signed C̄ (`/correlation/xi`) is listed beside it: it is a harmonic "
        "mean of contact distances in dilute flows and loses its meaning where C̄ changes sign (its "
        "denominator crosses zero).",
        "",
        quote(
            "For small values of packing fraction, Figure 5.3 shows the value of ξ approaching a limiting "
            "value of 0.785σ.",
            "555",
        ),
        f"Ours: ξ_el = {ct.fmt_pm(res['xi_el'] / sigma, res['xi_el_error'] / sigma)}σ from "
        + ", ".join(f"`{os.path.basename(runs['input'][r])}`" for r in res["reference_rows"])
        + " (C̄ is a density per unit area, so isolated contacts give ξ ≈ the contact distance ≈ σ; "
        "only ξ/ξ_el compares with the thesis).",
        "",
    ]
    # ξ/ξ_el table, ν × e at μ = 0, with the P(f) decision.
    frictionless = ct.select(table, friction=0.0)
    es = np.unique(runs["restitution"][frictionless])
    nus = np.unique(runs["packing_fraction"][frictionless])
    lines += [
        quote(
            "We notice that ξ is an increasing function of density for each value of restitution. We also "
            "notice, in agreement with Figure 5.1, that ξ increases as e decreases.",
            "553",
        ),
        quote(
            "For ξ/ξ_el ≤ 1.25 there is a clear peak, whereas for ξ/ξ_el ≥ 1.25, the peak disappears and "
            "the maximum occurs at f = 0.",
            "645",
        ),
        "ξ_|C|/ξ_el for μ = 0; ▲ = gf-correlate finds a peak of P(f) at f > 0, ○ = maximum at f = 0 "
        "(bootstrap confidence < 80 % in brackets); † = correlations reach the box (more than "
        f"{100 * res['max_tail_share']:g} % of ∫ℓ|C| beyond 2ℓ_max/3): not measurable, left out below:",
        "",
        "| ν | " + " | ".join(f"e = {e:g}" for e in es) + " |",
        "|---|" + "---|" * len(es),
    ]
    for nu in nus:
        cells = []
        for e in es:
            r = ct.select(table, restitution=e, friction=0.0, packing_fraction=nu)
            if not len(r):
                cells.append("–")
                continue
            r = r[0]
            mark = "▲" if fo["peak"][r] == 1 else "○"
            conf = fo["peak_confidence"][r]
            cells.append(
                f"{ct.fmt_pm(res['ratio'][r], res['ratio_error'][r])}{'' if res['measurable'][r] else ' †'} "
                f"{mark}" + (f" ({100 * conf:.0f} %)" if conf < 0.8 else "")
            )
        lines.append(f"| {nu:.3f} | " + " | ".join(cells) + " |")
    # The statements, checked on the measurable runs.
    ok = res["measurable"]
    low = nus[0]
    low_rows = ct.select(table, friction=0.0, packing_fraction=low)
    dev = [(runs["restitution"][r], (res["ratio"][r] - 1) / res["ratio_error"][r]) for r in low_rows]
    rising, steps = 0, 0
    for e in es:
        r = ct.select(table, restitution=e, friction=0.0)
        x = res["xi"][r[ok[r]]]
        steps += len(x) - 1
        rising += int(np.sum(np.diff(x) > 0))
    ordered, pairs = 0, 0
    for nu in nus:
        r = ct.select(table, friction=0.0, packing_fraction=nu)
        r = r[ok[r]]
        r = r[np.argsort(runs["restitution"][r])]
        pairs += len(r) - 1
        ordered += int(np.sum(np.diff(res["xi"][r]) < 0))
    used = frictionless[ok[frictionless]]
    ratio, peak = res["ratio"][used], fo["peak"][used]
    dense, dilute = ratio >= thr, ratio < thr
    lines += [
        "",
        f"Ours: at the lowest ν = {low:.3f}, (ξ/ξ_el − 1)/error = "
        + ", ".join(f"{d:+.1f} (e = {e:g})" for e, d in dev)
        + f". Over the measurable runs, ξ grows with ν in {rising} of {steps} consecutive steps (all e) and "
        f"decreases with e in {ordered} of {pairs} neighbouring pairs at fixed ν. P(f): of the "
        f"{int(dense.sum())} runs with ξ/ξ_el ≥ {thr:g}, {int((peak[dense] == 0).sum())} have their maximum "
        f"at f = 0; of the {int(dilute.sum())} runs with ξ/ξ_el < {thr:g}, {int((peak[dilute] == 1).sum())} "
        "have a peak at f > 0 (the thesis: all of them). Where the peak goes, per e, is in the next table.",
        "",
    ]
    # ν_bc per series.
    sweep = table.get("sweep", {})
    lines += [
        quote(
            "This plot is for frictionless materials μ = 0, but increasing the value of μ does not change "
            "the curve.",
            "668",
        ),
        "Peak gone from ν: the lowest ν from which every run of the series has its P(f) maximum at f = 0.",
        "",
        "| e | μ | runs | ν_bc (ξ_|C|) | status | ν_bc (gf-correlate, signed ξ) | P(f) peak gone from ν |",
        "|---|---|---|---|---|---|---|",
    ]
    status_names = {0: "bracketed", 1: "all_above", 2: "all_below", 3: "too_few", 4: "only_downward"}
    for s in res["series"]:
        gf = "–"
        if sweep:
            k = np.flatnonzero(
                (np.abs(sweep["restitution"] - s["restitution"]) < 1e-6)
                & (np.abs(sweep["friction"] - s["friction"]) < 1e-6)
            )
            if len(k):
                k = k[0]
                gf = (
                    ct.fmt_pm(sweep["nu_bc"][k], sweep["nu_bc_error"][k])
                    if sweep["status"][k] == 0
                    else status_names.get(int(sweep["status"][k]), "?")
                )
        series_rows = ct.select(table, restitution=s["restitution"], friction=s["friction"])
        peaks = fo["peak"][series_rows]
        gone = [runs["packing_fraction"][series_rows][i] for i in range(len(peaks)) if (peaks[i:] == 0).all()]
        lines.append(
            f"| {s['restitution']:g} | {s['friction']:g} | {s['runs']} | "
            f"{ct.fmt_pm(s['nu_bc'], s['nu_bc_error']) if s['status'] == 'bracketed' else '–'} | "
            f"{s['status']} | {gf} | {f'{gone[0]:.3f}' if gone else 'never'} |"
        )
    # Anisotropy: every frictionless run with a well-defined eq.-5.2 ξ.
    ok = frictionless[
        (cor["xi"][frictionless] > 0)
        & (cor["xi_error"][frictionless] < 0.2 * cor["xi"][frictionless])
        & res["measurable"][frictionless]
    ]
    if len(ok):
        th = cor["theta"]
        fit = ct.fit_anisotropy(
            np.tile(th, len(ok)),
            np.concatenate([2 * np.pi * cor["xi_theta"][r] / cor["xi"][r] for r in ok]),
            np.concatenate([2 * np.pi * cor["xi_theta_error"][r] / cor["xi"][r] for r in ok]),
            float(np.pi / len(th)),
        )
        lines += [
            "",
            quote(
                "The solid curve in Figure 5.6 is a fit to this equation, which sets the parameters as "
                "a_0 = 0.21 and θ_0 = 0.013.",
                "605",
            ),
            f"Ours (gf-correlate's ξ(θ), {len(ok)} runs with δξ/ξ < 0.2, pooled fit of eq. 5.3): a0 = "
            f"{ct.fmt_pm(fit['a0'], fit['a0_error'])}, θ0 = {ct.fmt_pm(fit['theta0'], fit['theta0_error'])} "
            f"(χ²/dof = {fit['chi2_dof']:.2g}); per-run a0 from {np.nanmin(cor['a0'][ok]):.2f} to "
            f"{np.nanmax(cor['a0'][ok]):.2f}.",
        ]
    # The decay length per direction, ξ_|C|(θ), over every measurable frictionless run.
    ok_abs = frictionless[res["measurable"][frictionless]] if "xi_abs_theta" in cor else []
    if len(ok_abs):
        th = cor["theta"]
        mean = np.nanmean(cor["xi_abs_theta"][ok_abs], axis=1)
        fit = ct.fit_anisotropy(
            np.tile(th, len(ok_abs)),
            np.concatenate([cor["xi_abs_theta"][r] / m for r, m in zip(ok_abs, mean)]),
            np.concatenate([cor["xi_abs_theta_error"][r] / m for r, m in zip(ok_abs, mean)]),
            float(np.pi / len(th)),
        )
        dense = ok_abs[res["ratio"][ok_abs] >= thr]
        lines += [
            "",
            f"Ours, decay length per direction (gf-correlate's ξ_|C|(θ) over its mean, {len(ok_abs)} "
            f"measurable runs, pooled fit of eq. 5.3's shape): a0 = {ct.fmt_pm(fit['a0'], fit['a0_error'])}, "
            f"θ0 = {ct.fmt_pm(fit['theta0'], fit['theta0_error'])} (χ²/dof = {fit['chi2_dof']:.2g})"
            + (
                f"; per-run a0 over the {len(dense)} runs with ξ/ξ_el ≥ {thr:g}: "
                f"{np.nanmin(cor['a0_abs'][dense]):.2f} to {np.nanmax(cor['a0_abs'][dense]):.2f}"
                if len(dense)
                else ""
            )
            + ".",
        ]
    # Clusters (Fig. 5.1).
    if clusters_path:
        cl_table = ct.read_table(clusters_path)
        cl, cr = cl_table["clusters"], cl_table["runs"]
        lines += [
            "",
            quote(
                "For e = 0.92 the interacting grains are well spaced and tend to occur in pairs, whereas "
                "for e = 0 the interacting grains tend to form large clusters.",
                "510",
            ),
            "| run | window (steps) | grains in contact | clusters | largest | mean size |",
            "|---|---|---|---|---|---|",
        ]
        for i in range(len(cr["input"])):
            labels = cl["label"][cl["grain_offset"][i] : cl["grain_offset"][i + 1]]
            sizes = np.bincount(labels)[1:]
            sizes = sizes[sizes > 0]
            lines.append(
                f"| `{os.path.basename(cr['input'][i])}` | "
                f"{int(cl['last_step'][i] - cl['first_step'][i]) + 1} | {int((labels > 0).sum())} | "
                f"{len(sizes)} | {sizes.max() if len(sizes) else 0} | "
                f"{sizes.mean() if len(sizes) else 0:.2f} |"
            )
    return lines


def ch5_jamming_section(jamming_path):
    """ν_c(μ, e) from the divergence of the steady stresses (jamming_point.py), beside §5.2."""
    table = outputs.read_table(jamming_path, ("fits", "skipped"))
    fits, skipped, prm = table["fits"], table["skipped"], table["parameters"]
    lines = [
        "",
        "### ν_c from the steady stresses (jamming_point.py)",
        "",
        quote(
            "The data in Figures 5.3 and 5.4 demonstrates that ξ diverges at a finite packing fraction ν_c "
            "that depends on the friction coefficient μ, but not on the restitution coefficient e.",
            "568",
        ),
        f"Table `{jamming_path}`: per (μ, e), the runs at ν ≥ {float(prm['from_nu']):g} fitted to "
        "q = A (ν_c − ν)^−β, q = p/(mγ̇²) or s/(mγ̇²) (weighted least squares in ln q; ν_c's interval where "
        "χ² stays within max(1, χ²/dof) of its minimum; `pipelines/analysis/jamming_point.py`). The thesis "
        "estimates ν_c ≈ 0.845 at μ = 0 (Fig. 5.10). An extrapolation: ν_c lies above every run.",
    ]
    keys = sorted({(float(m), float(e)) for m, e in zip(fits["friction"], fits["restitution"])})
    if keys:
        lines += [
            "",
            "| μ | e | runs | densest ν | ν_c from p, β free | β | χ²/dof | ν_c from p, β = 2 | ν_c from s, β free | β |",
            "|---|---|---|---|---|---|---|---|---|---|",
        ]

    def interval(i):
        hi = fits["nu_c_high"][i]
        return (f"{fits['nu_c'][i]:.4f} [{fits['nu_c_low'][i]:.4f}, "
                + (f"{hi:.4f}]" if math.isfinite(hi) else "∞)"))

    quantity = list(fits["quantity"])
    free = np.isnan(fits["exponent_fixed"])
    for mu, e in keys:
        group = (fits["friction"] == mu) & (fits["restitution"] == e)

        def row(q, fixed=None):
            pick = group & np.array([x == q for x in quantity])
            pick &= free if fixed is None else (fits["exponent_fixed"] == fixed)
            return int(np.flatnonzero(pick)[0]) if pick.any() else None

        p, p2, sh = row("pressure_scaled"), row("pressure_scaled", 2.0), row("shear_stress_scaled")
        lines.append(
            f"| {mu:g} | {e:g} | {int(fits['points'][p])} | {fits['nu_max'][p]:g} | {interval(p)} | "
            f"{fits['exponent'][p]:.2f} | {fits['chi2'][p]:.1f}/{int(fits['dof'][p])} | "
            + (interval(p2) if p2 is not None else "—")
            + f" | {interval(sh)} | {fits['exponent'][sh]:.2f} |"
        )
    if len(skipped["friction"]):
        lines.append("")
        lines.append(
            f"Not fitted (fewer than {jamming_point.MIN_POINTS} runs at ν ≥ {float(prm['from_nu']):g}): "
            + ", ".join(f"μ = {m:g}, e = {e:g} ({int(n)})"
                        for m, e, n in zip(skipped["friction"], skipped["restitution"], skipped["points"]))
            + "."
        )
    return lines


def ch6_section(kinetic_path, correlate_path):
    """Chapter 6, kinetic theory: gf-kinetic's stresses and predictions beside the statements of
    thesis §6.1 (every number from the tables; "not measured" where a dataset is NaN)."""
    table = kt.read_table(kinetic_path)
    runs, attrs = table["runs"], table["runs"]["attrs"]
    ratio, _, measurable = kt.xi_ratio(table, ct.read_table(correlate_path))
    full = kt.filled(ratio, measurable)
    nu = kt.column(table, "packing_fraction")
    baseline = float(attrs.get("velocity_correlation_baseline", -0.25))
    frictionless = np.abs(kt.column(table, "friction")) < 1e-9
    es = sorted({float(e) for e in kt.column(table, "restitution")[frictionless]}, reverse=True)
    eq = table.get("equilibrium")
    chi_source = np.asarray(runs.get("chi_source", np.full(len(nu), -1)), dtype=int)
    lines = [
        "",
        "## Chapter 6: kinetic theory (thesis §6.1, Figs 6.1–6.3)",
        "",
        f"Table `{kinetic_path}` (gf-kinetic, one row per run): {len(nu)} runs, N = {int(np.max(runs['grains']))}"
        + (
            f", χ interpolated from {len(eq['packing_fraction'])} equilibrium runs (e = 1, γ̇ = 0) at ν = "
            + ", ".join(f"{v:.3f}" for v in eq["packing_fraction"])
            if eq is not None
            else ", no equilibrium runs: χ from Henderson's formula"
        )
        + f" ({int(np.sum(chi_source == 1))} runs extrapolated, {int(np.sum(chi_source == 2))} from Henderson's "
        f"formula). ξ/ξ_el from `{correlate_path}` (gf-correlate's ξ_|C|, matched by run path; "
        f"{int(np.sum(np.isfinite(ratio)))} of {len(nu)} runs found there). “Agree within errors”: "
        f"|a − b| ≤ {kt.AGREE_SIGMAS:g} combined blocked standard errors. Velocity correlation convention: "
        f"{attrs.get('velocity_correlation_convention', 'not stated')}, molecular-chaos baseline {baseline:g}.",
        "",
    ]
    if eq is not None:
        lines += [
            "Equilibrium runs (χ from the collision frequency, ω = √(2π T) χ n σ, beside the virial estimate "
            "and Henderson's formula):",
            "",
            "| ν | energy drift | T drift | χ (collisions) | χ (virial) | χ Henderson |",
            "|---|---|---|---|---|---|",
        ]
        for i in range(len(eq["packing_fraction"])):
            g = lambda name: float(eq[name][i]) if name in eq else kt.NAN  # noqa: E731
            lines.append(
                f"| {g('packing_fraction'):.3f} | {kt.fmt_percent(g('energy_drift'))} | "
                f"{kt.fmt_percent(g('temperature_drift'))} | "
                f"{kt.fmt_pm(g('chi'), g('chi_error'))} | {kt.fmt_pm(g('chi_virial'), g('chi_virial_error'))} | "
                f"{kt.fmt_ratio(g('chi_henderson'))} |"
            )
        lines.append("")
    # The binary-collision range and the pressure prediction, per e.
    lines += [
        quote(
            "For now, it is only important to notice that there is a regime where the binary collision "
            "assumption holds and the normalized stress tensors are equal. The bounds of this regime depend "
            "on the value of both the restitution coefficient and the packing fraction.",
            "739",
        ),
        quote(
            "We immediately notice that the prediction for the pressure matches the measured pressure in all "
            "of the dilute systems we have investigated.",
            "798",
        ),
        "Per e (μ = 0): the ν range, from the most dilute run on, where p^bc = p^s within errors; the largest ν "
        f"up to which the Enskog pressure holds within {100 * kt.PRESSURE_TOLERANCE:g} % (|p^s/(p⁰(1+e)χν) − 1|, "
        "eq. 6.9); the largest ν with ξ/ξ_el ≤ 1.25 (open points of the figures).",
        "",
        "| e | runs | ν range p^bc = p^s | agree again at | p^s/p_enskog within 5 % up to | p^s/p_enskog at "
        "the most dilute ν | last open point (ξ/ξ_el ≤ 1.25) |",
        "|---|---|---|---|---|---|---|",
    ]
    for e in es:
        rows = kt.select(table, e)
        rows = rows[frictionless[rows]]
        if len(rows) == 0:
            continue
        upto, again = kt.dilute_range(nu[rows], kt.pressures_agree(table, rows))
        holds, pratio = kt.pressure_prediction_holds(table, rows)
        pupto, _ = kt.dilute_range(nu[rows], holds)
        open_rows = rows[~full[rows] & np.isfinite(ratio[rows])]
        lines.append(
            f"| {e:g} | {len(rows)} | "
            + (f"{nu[rows][0]:.3f}–{upto:.3f}" if np.isfinite(upto) else "none (differ at the most dilute ν)")
            + f" | {', '.join(f'{v:.3f}' for v in again) or '–'} | {kt.fmt_nu(pupto)} | {kt.fmt_ratio(pratio[0])} | "
            f"{kt.fmt_nu(np.max(nu[open_rows])) if len(open_rows) else 'none'} |"
        )
    # Which shear-stress prediction the dilute e = 0.92 data follow.
    lines += [
        "",
        quote(
            "The prediction for the shear stress also matches the data in the dilute regime quite well for "
            "large restitution.",
            "800",
        ),
    ]
    high = kt.select(table, 0.92)
    high = high[frictionless[high]]
    if len(high):
        r = high[0]
        s_thesis = kt.column(table, "s_static")[r] / kt.column(table, "s_enskog_thesis")[r]
        s_2d = kt.column(table, "s_static")[r] / kt.column(table, "s_enskog_2d")[r]
        lines.append(
            f"Ours, e = 0.92 at the most dilute ν = {nu[r]:.3f}: s^s/s_pred = {kt.fmt_ratio(s_thesis)} for eq. 6.10 "
            f"as printed, {kt.fmt_ratio(s_2d)} for the 2D Garzó–Dufty viscosity "
            f"(s^s = {kt.fmt_pm(kt.column(table, 's_static')[r], kt.column(table, 's_static_error')[r])}): "
            f"the data follow **{kt.closer_prediction(s_thesis, s_2d)}** more closely."
        )
    else:
        lines.append("Ours: no run at e = 0.92: not measured.")
    # C_v beside the shear-stress error, on the open points.
    lines += [
        "",
        quote(
            "This definition yields a positive value when pre-collisional grain velocities tend to be aligned, "
            "and for all restitution coefficients we observe that the correlations are positive. In addition, "
            "the magnitude of the discrepancy between measured and predicted shear stress is roughly "
            "proportional to the size of the velocity correlations.",
            "806",
        ),
        f"Ours, on the open points (ξ/ξ_el ≤ 1.25), per e: C_v and its sign against the molecular-chaos "
        f"baseline {baseline:g} (and against 0, the sign the thesis reads), and the relative shear-stress "
        "error (s_pred − s^s)/s^s of both predictions at the same runs:",
        "",
        "| e | ν | C_v | C_v − baseline | sign vs baseline | sign vs 0 | (s_6.10 − s^s)/s^s | (s_2D − s^s)/s^s |",
        "|---|---|---|---|---|---|---|---|",
    ]
    cv, cv_err = kt.column(table, "velocity_correlation"), kt.column(table, "velocity_correlation_error")
    pooled = []
    for e in es:
        rows = kt.select(table, e)
        rows = rows[frictionless[rows] & ~full[rows] & np.isfinite(ratio[rows])]
        err_thesis, err_2d = kt.shear_error(table, rows, "s_enskog_thesis"), kt.shear_error(table, rows, "s_enskog_2d")
        for k, r in enumerate(rows):
            lines.append(
                f"| {e:g} | {nu[r]:.3f} | {kt.fmt_pm(cv[r], cv_err[r])} | {kt.fmt_pm(cv[r] - baseline, cv_err[r])} | "
                f"{kt.sign_word(cv[r], cv_err[r], baseline)} | {kt.sign_word(cv[r], cv_err[r])} | "
                f"{kt.fmt_ratio(err_thesis[k])} | {kt.fmt_ratio(err_2d[k])} |"
            )
            pooled.append((cv[r] - baseline, err_thesis[k], err_2d[k], kt.sign_word(cv[r], cv_err[r], baseline)))
    if pooled:
        excess, et, e2, signs = (np.array([p[i] for p in pooled]) for i in range(4))
        r_thesis, n_thesis = kt.proportionality(excess, et)
        r_2d, n_2d = kt.proportionality(excess, e2)
        counts = {w: int(np.sum(signs == w)) for w in ("positive", "negative", "zero within errors", "not measured")}
        lines += [
            "",
            f"Over the {len(pooled)} open points: C_v − baseline is positive in {counts['positive']}, negative in "
            f"{counts['negative']}, zero within errors in {counts['zero within errors']}, not measured in "
            f"{counts['not measured']}. Pearson's r between C_v − baseline and the relative shear-stress error: "
            f"{kt.fmt_ratio(r_thesis)} for eq. 6.10 as printed ({n_thesis} points), {kt.fmt_ratio(r_2d)} for "
            f"2D Garzó–Dufty ({n_2d} points) (r near 1: the thesis' “roughly proportional”).",
        ]
    else:
        lines += ["", "No open points with a ξ/ξ_el: not measured."]
    return lines


def ch6_network_section(network_path, halfstep_path=None):
    """Chapter 6, the force-network model (thesis §6.2, Figs 6.5–6.8): gf-network's Φ, Ψ, z,
    Fourier components and both sides of eqs. 6.27–6.29 beside the thesis' statements (every
    number from the tables; "not measured" where a dataset is NaN)."""
    table = nt.read_table(network_path)
    n = nt.rows(table)
    nu, e = nt.column(table, "packing_fraction"), nt.column(table, "restitution")
    where = lambda r: f"ν = {nu[r]:.3f}, e = {e[r]:g}"  # noqa: E731
    xi_source = table["prediction"]["attrs"].get("xi_source", "correlation")
    lines = [
        "",
        "## Chapter 6: the force-network model (thesis §6.2, Figs 6.5–6.8)",
        "",
        f"Table `{network_path}` (gf-network, one row per run): {n} runs, N = {int(np.max(table['runs']['grains']))}; "
        "z counts long-lived contacts (in contact with an impulse in this step and the previous one) over all "
        "grains, Φ and Ψ are twice the means of cos x and cos x cos 2x over pairs of long-lived contacts of one "
        "grain (eq. 6.23's normalisation). ξ/ξ_el: "
        + (
            "none (the table was made without --correlation: no right-hand sides)."
            if xi_source == "none"
            else f"gf-correlate's table, {int(np.sum(nt.column(table, 'xi_measurable', 'prediction') > 0))} of {n} "
            "runs with a measurable ξ."
        )
        + f" “Agree within errors”: |a − b| ≤ {nt.AGREE_SIGMAS:g} combined standard errors.",
        "",
    ]
    # Φ and Ψ.
    phi, phi_err = nt.column(table, "Phi"), nt.column(table, "Phi_error")
    lo, hi = nt.value_range(phi)
    below, finite, exceptions = nt.psi_below_phi(table)
    lines += [
        quote(
            "Although z and Ψ depend sensitively on the value of ν and e , the value of Φ is always "
            "approximately 0.83.",
            "953",
        ),
        quote("We observe that $\\Psi < \\Phi$ for all granular materials we have considered.", "955"),
    ]
    if finite:
        rlo, rhi = int(np.nanargmin(phi)), int(np.nanargmax(phi))
        lines.append(
            f"Ours: Φ from {nt.fmt_pm(phi[rlo], phi_err[rlo])} ({where(rlo)}) to {nt.fmt_pm(phi[rhi], phi_err[rhi])} "
            f"({where(rhi)}) over {finite} runs (range {lo:.3f}–{hi:.3f}, thesis ≈ {nt.THESIS_PHI:g}); "
            f"Ψ < Φ in {below} of {finite} runs"
            + (f" (not at {'; '.join(where(r) for r in exceptions)})." if len(exceptions) else ".")
        )
    else:
        lines.append("Ours: Φ and Ψ not measured (no run with pairs of long-lived contacts).")
    # The next Fourier order.
    lines += [
        "",
        quote(
            "The size of the components is always of order 10^{-1} whereas the magnitude of the next order "
            "coefficients in the Fourier Series is less than 10^{-2} .",
            "910",
        ),
    ]
    parts = []
    for names, what in ((("a4_c", "a4_c_prime"), "C(θ)"), (("a4_f", "a4_f_prime"), "F_bc(θ)")):
        value, error, name, row = nt.largest_abs(table, names)
        large, counted = nt.count_at_least(table, names, nt.THESIS_NEXT_ORDER)
        if name is None:
            parts.append(f"the 4θ components of {what} not measured")
        else:
            parts.append(
                f"the largest 4θ component of {what} is {name} = {nt.fmt_pm(value, error)} ({where(row)}); "
                f"{large} of {counted} runs have a 4θ component of {what} with |value| ≥ {nt.THESIS_NEXT_ORDER:g}"
            )
    first_order = nt.largest_abs(table, ("a_c", "a_c_prime", "a_f", "a_f_prime"))
    lines.append(
        "Ours: "
        + "; ".join(parts)
        + ". The largest first-order component: "
        + (
            f"{first_order[2]} = {nt.fmt_pm(first_order[0], first_order[1])} ({where(first_order[3])})."
            if first_order[2]
            else "not measured."
        )
    )
    # z at two time steps.
    lines += ["", quote("This measurement of z does not depend on the time step, as is shown in the inset.", "955")]
    if halfstep_path:
        half = nt.read_table(halfstep_path)
        pairs = nt.step_pairs(half)
        if pairs:
            z, dz = nt.column(half, "coordination"), nt.column(half, "coordination_error")
            hnu, he = nt.column(half, "packing_fraction"), nt.column(half, "restitution")
            lines += ["| ν | e | z (default step) | z (half step) | difference |", "|---|---|---|---|---|"]
            diffs = []
            for i, j in pairs:
                d = float(nt.difference_sigmas(z[j], dz[j], z[i], dz[i]))
                diffs.append(d)
                lines.append(
                    f"| {hnu[i]:.3f} | {he[i]:g} | {nt.fmt_pm(z[i], dz[i])} | {nt.fmt_pm(z[j], dz[j])} | "
                    f"{nt.fmt_sigmas(d)} |"
                )
            k = nt.largest_finite(diffs)
            agree = sum(1 for d in diffs if np.isfinite(d) and abs(d) <= nt.AGREE_SIGMAS)
            lines += [
                "",
                f"Ours (`{halfstep_path}`): {len(pairs)} pairs of runs at the default step and half of it; the largest "
                "difference of z (half − default) is "
                + (
                    f"{nt.fmt_sigmas(diffs[k])} (ν = {hnu[pairs[k][0]]:.3f}, e = {he[pairs[k][0]]:g})"
                    if k is not None
                    else "not measured"
                )
                + f"; z agrees within errors in {agree} of {len(pairs)} pairs.",
            ]
        else:
            lines.append(f"Ours: `{halfstep_path}` has no pair of runs with equal ν, e and dt ratio 2: not measured.")
    else:
        lines.append("Ours: no half-step runs: not measured.")
    # Fig. 6.8's collapse.
    lines += [
        "",
        quote(
            "Plotted in this way, the data for each component of the stress tensor collapses onto the line "
            "predicted by the force-network model over at least four decades.",
            "957",
        ),
        "Ours: log10 lhs against log10 rhs over the runs with both sides positive (a perfect collapse: slope 1, "
        "scatter 0). Scatter = rms of log10(lhs/rhs) in decades (dex); decades = the span of log10 rhs (of log10 "
        "lhs in brackets) over those runs; rows left out because a side is ≤ 0, or without a value (no ξ/ξ_el). "
        "Readings: " + "; ".join(f"{r[1:] or 'main'} = {text}" for r, text in nt.READINGS) + ".",
        "",
        "| eq. | reading | slope | scatter (dex) | runs used | side ≤ 0 | no value | decades rhs (lhs) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for c in nt.collapse_table(table):
        lines.append(
            f"| {c['number']} | {c['reading'][1:] or 'main'} | {nt.fmt_number(c['slope'])} | "
            f"{nt.fmt_number(c['scatter'])} | {c['used']} | {c['non_positive']} | {c['missing']} | "
            f"{nt.fmt_number(c['decades_rhs'], 2)} ({nt.fmt_number(c['decades_lhs'], 2)}) |"
        )
    # Only a run with a sum limit can lack a real continuation.
    real = nt.column(table, "continuation_real", "prediction")
    limited = np.isfinite(nt.column(table, "sum_limit", "prediction"))
    lines += [
        "",
        f"{int(np.sum(limited & (real == 0)))} of {int(np.sum(limited))} runs with a ξ/ξ_el have a negative base "
        "with a non-integer ξ/ξ_el − 1 (no real continuation of the sums: their main reading is the floor one).",
    ]
    # Eq. 6.27's bound, whatever the reading: the measured excess against ξ/ξ_el − 1.
    excess = nt.bound_excess(table)
    measured = np.isfinite(excess)
    above = measured & (excess > nt.AGREE_SIGMAS)
    kb = nt.largest_finite(np.where(measured, excess, np.nan))
    lines += [
        "",
        "With 0 ≤ min[Φ(z − 1), 1] ≤ 1 the right-hand side of eq. 6.27 is at most ξ/ξ_el − 1 (every link passes "
        "its whole force on), whatever z, Φ and the reading of the sums. Ours: (p^s − p^bc)/p^bc exceeds ξ/ξ_el − 1 "
        f"by more than {nt.AGREE_SIGMAS:g} combined errors in {int(above.sum())} of {int(measured.sum())} runs with "
        "a ξ/ξ_el"
        + (
            f" (largest: {where(kb)}, {nt.fmt_pm(nt.column(table, 'lhs_pressure', 'prediction')[kb], nt.column(table, 'lhs_pressure_error', 'prediction')[kb])} "
            f"against ξ/ξ_el − 1 = {nt.fmt_number(nt.column(table, 'sum_limit', 'prediction')[kb], 2)})."
            if kb is not None
            else "."
        ),
    ]
    # σ(θ) and the identity s^bc/p^bc = −2χ12.
    ratio, ratio_err, target, target_err, sig = nt.identity_deviation(table)
    frames = nt.identity_deviation(table, frames=True)
    aniso = nt.value_range(nt.column(table, "sigma_anisotropy"))
    maxdev = nt.value_range(nt.column(table, "sigma_max_deviation"))
    k, kf = nt.largest_finite(sig), nt.largest_finite(frames[4])
    lines += [
        "",
        "The identity s^bc/p^bc = −2χ12 (s = −Σxy) holds when the contact distance σ(θ) does not depend on θ. "
        f"Ours: the 2θ amplitude of σ(θ)/⟨σ⟩ from {nt.fmt_number(aniso[0], 4)} to {nt.fmt_number(aniso[1], 4)}, "
        f"the largest |σ_k/⟨σ⟩ − 1| of a θ bin from {nt.fmt_number(maxdev[0], 4)} to {nt.fmt_number(maxdev[1], 4)}. "
        "s^bc/p^bc from the stress rows against −2χ12: "
        + (
            f"largest difference {nt.fmt_sigmas(sig[k])} ({where(k)}: {nt.fmt_pm(ratio[k], ratio_err[k])} against "
            f"{nt.fmt_pm(target[k], target_err[k])}), within errors in "
            f"{int(np.sum(np.abs(sig[np.isfinite(sig)]) <= nt.AGREE_SIGMAS))} of {int(np.sum(np.isfinite(sig)))} runs"
            if k is not None
            else "not measured"
        )
        + "; from the frames' contacts (exact whatever σ(θ)): "
        + (f"largest difference {nt.fmt_sigmas(frames[4][kf])} ({where(kf)})." if kf is not None else "not measured."),
    ]
    return lines


def ch6_d2min_section(maps_path):
    """Chapter 6, Fig. 6.9: black fractions, clusters and overlaps of the D²min maps
    (d2min_maps.py's table), at its default threshold and over its sweep."""
    table = d2min_maps.read_table(maps_path)
    maps, default, sweep, par = table["maps"], table["default"], table["sweep"], table["parameters"]
    threshold = default["threshold"]
    t = sweep["threshold"]
    pct = lambda v: f"{100 * v:.1f} %" if math.isfinite(v) else "–"  # noqa: E731
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
        quote(
            "We notice that there is a tendency for the regions of non-affine displacement to form clusters, "
            "and the size of the resulting non-affine regions is about the same in both (a) and (b).",
            "1008",
        ),
        quote(
            "comparing (a) and (d), we notice that the size of the non-affine regions is about the same in the "
            "two figures, but the locations are different.",
            "1015",
        ),
        f"| map | strain | grains (valid) | black at {threshold:g} | clusters | largest | mean size | "
        "cluster sizes (count × size) | black over the sweep |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for k, label in enumerate(maps["label"]):
        hist = default["cluster_size_histogram"][k]
        sizes = ", ".join(f"{int(c)}×{s + 1}" for s, c in enumerate(hist) if c)
        frac = sweep["black_fraction"][k]
        lines.append(
            f"| ({label}) | {maps['start_strain'][k]:g} → {maps['end_strain'][k]:g} | {int(maps['grains'][k])} "
            f"({int(maps['valid_count'][k])}) | {pct(default['black_fraction'][k])} | "
            f"{int(default['cluster_count'][k])} | {int(default['largest_cluster'][k])} | "
            f"{stz.fmt(float(default['mean_cluster_size'][k]))} | {sizes or '–'} | "
            f"{pct(np.nanmin(frac))} – {pct(np.nanmax(frac))} |"
        )
    lines += [
        "",
        "Overlap of the black sets, Jaccard index J = |A ∩ B|/|A ∪ B| over the grains valid in both, against "
        "the value of two independent random sets of the same fractions (chance):",
        "",
        f"| pair | J at {threshold:g} | chance | J / chance | J over the sweep | J / chance over the sweep |",
        "|---|---|---|---|---|---|",
    ]
    for p, pair in enumerate(default["pair"]):
        j, c = float(default["jaccard"][p]), float(default["jaccard_chance"][p])
        js, cs = sweep["jaccard"][p], sweep["jaccard_chance"][p]
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = js / cs
        finite = np.isfinite(js)
        span = f"{np.min(js[finite]):.3f} – {np.max(js[finite]):.3f}" if finite.any() else "–"
        rfinite = np.isfinite(ratio)
        rspan = f"{np.min(ratio[rfinite]):.2f} – {np.max(ratio[rfinite]):.2f}" if rfinite.any() else "–"
        lines.append(
            f"| {pair} | {stz.fmt(j)} | {stz.fmt(c)} | {stz.fmt(j / c if c > 0 else math.nan)} | {span} | {rspan} |"
        )
    return lines


def ch6_stz_section(fit_path, critical_path=None):
    """Chapter 6, the STZ law (thesis §6.3, Figs 6.10, 6.11): gf-stz fit's coefficients per μ, θ*
    against the incline's θ_c, the rms residuals of the fitted and predicted points, and the STZ law
    against μ(I) (every number from the table)."""
    table = stz.read_table(fit_path)
    fit, attrs = table["fit"], table["fit_attrs"]
    col = lambda n: stz.column(table, n, "fit")  # noqa: E731
    runs_kind = stz.kinds(table)
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
        quote(
            "The line is the STZ prediction, which fits the data very well.",
            "1055",
        ),
        quote("find that the incline flow data is predicted using the exact same coefficients!", "1077"),
        "| μ | points | A | κ | ζ | tanθ* | θ* (°) | θ* jackknife error (°) | χ²/dof | μ_s | μ₂ | I₀ |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    pm = lambda n, r: stz.fmt_pm(col(n)[r], col(n + "_error")[r])  # noqa: E731

    def jackknife(r):
        """θ*'s delete-one jackknife error in degrees (NaN in tables without the column)."""
        return col("theta_star_jackknife_error")[r] if "theta_star_jackknife_error" in fit else math.nan

    order = np.argsort(col("friction"))
    for r in order:
        dof = int(fit["dof"][r]) if "dof" in fit else 0
        chi = f"{col('chi2')[r]:.3g}/{dof}" if math.isfinite(col("chi2")[r]) else "–"
        lines.append(
            f"| {col('friction')[r]:g} | {int(fit['points'][r]) if 'points' in fit else '–'} | {pm('A', r)} | "
            f"{pm('kappa', r)} | {pm('zeta', r)} | {pm('tan_theta_star', r)} | {pm('theta_star', r)} | "
            f"{stz.fmt(jackknife(r))} | {chi} | {pm('mu_s', r)} | {pm('mu_2', r)} | {pm('I0', r)} |"
        )
    degenerate = [
        f"{col('friction')[r]:g}"
        for r in order
        if any(not (abs(col(n + "_error")[r]) < 100 * abs(col(n)[r])) for n in ("A", "kappa", "zeta"))
    ]
    if degenerate:
        lines += [
            "",
            f"At μ = {', '.join(degenerate)} A, κ and ζ are not determined one by one (an error above 100 times the "
            "value): the points lie near the κ → 0 limit of eq. 6.36, x ≈ c₁μ − c₂/μ (Aκ = c₁, A/ζ = c₂), which "
            "fixes tanθ* = √(c₂/c₁) but not the three coefficients; the delta-method error of θ* is then NaN and "
            "the jackknife error (refits without each point) stands.",
        ]
    lines += [
        "",
        "rms residuals in s/p (count):",
        "",
        "| μ | STZ fitted | μ(I) fitted | better on the fitted points | STZ predicted | μ(I) predicted | "
        "STZ incline | μ(I) incline |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in order:
        a, b = col("stz_rms")[r], col("mu_of_I_rms")[r]
        better = (
            "–" if not (math.isfinite(a) and math.isfinite(b)) else ("STZ" if a < b else "μ(I)" if b < a else "equal")
        )
        pc = int(fit["predicted_count"][r]) if "predicted_count" in fit else 0
        ic = int(fit["incline_count"][r]) if "incline_count" in fit else 0
        lines.append(
            f"| {col('friction')[r]:g} | {stz.fmt(a)} | {stz.fmt(b)} | {better} | {stz.fmt(col('predicted_rms')[r])} "
            f"({pc}) | {stz.fmt(col('mu_of_I_predicted_rms')[r])} ({pc}) | {stz.fmt(col('incline_rms')[r])} ({ic}) | "
            f"{stz.fmt(col('mu_of_I_incline_rms')[r])} ({ic}) |"
        )
    # The predicted shear runs split by the dense rule: the thesis claims the dense ones only.
    rcol = lambda n: stz.column(table, n)  # noqa: E731
    dense_flag = np.asarray(table["runs"]["dense"]).astype(bool)
    fitted_flag = np.asarray(table["runs"]["fitted"]).astype(bool)
    lines += [
        "",
        "The predicted shear runs (not fitted) split by the dense rule, rms residual in s/p (count):",
        "",
        "| μ | STZ, dense | μ(I), dense | STZ, dilute | μ(I), dilute |",
        "|---|---|---|---|---|",
    ]

    for r in order:
        mine = (runs_kind == "shear") & stz.same(rcol("friction"), col("friction")[r]) & ~fitted_flag
        cells = []
        for which in (dense_flag, ~dense_flag):
            for name in ("residual", "residual_mu_of_I"):
                values = rcol(name)[mine & which]
                cells.append(f"{stz.fmt(stz.rms(values))} ({int(np.sum(np.isfinite(values)))})")
        lines.append(f"| {col('friction')[r]:g} | " + " | ".join(cells) + " |")
    incline = np.flatnonzero(runs_kind == "incline")
    if len(incline):
        get = lambda n: stz.column(table, n)  # noqa: E731
        lines += [
            "",
            "Incline bulk points against the shear fit of their μ:",
            "",
            "| input | μ | e | γ̇⟨R⟩/√T | s/p | STZ | residual | μ(I) residual |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for r in incline:
            lines.append(
                f"| `{os.path.basename(str(table['runs']['input'][r]))}` | {get('friction')[r]:g} | "
                f"{get('restitution')[r]:g} | {stz.fmt_pm(get('rate_R_over_sqrt_T')[r], get('rate_R_over_sqrt_T_error')[r])} "
                f"| {stz.fmt_pm(get('s_over_p')[r], get('s_over_p_error')[r])} | {stz.fmt(get('prediction')[r])} | "
                f"{stz.fmt(get('residual')[r])} | {stz.fmt(get('residual_mu_of_I')[r])} |"
            )
    if critical_path:
        crit = ca.read_table(critical_path)
        res, cr = crit["critical_angle"], crit["runs"]
        theta_c, half = float(res["theta_c"]), float(res["half_width"])
        e_c = float(cr["restitution"][0]) if len(cr["restitution"]) else math.nan
        mu_c = float(cr["friction"][0]) if len(cr["friction"]) else math.nan
        row = stz.fit_row(table, mu_c) if math.isfinite(mu_c) else None
        lines += [
            "",
            quote(
                "θ^* is identified as the repose angle of the granular material, whose value is predicted by STZ theory.",
                "1045",
            ),
        ]
        if row is None or not math.isfinite(theta_c):
            lines.append(
                f"θ* against the incline's critical angle: not compared (θ_c = {stz.fmt(theta_c)}°, μ = {stz.fmt(mu_c)}: "
                "no fit of that μ or no θ_c)."
            )
        else:
            ts, tse = col("theta_star")[row], col("theta_star_error")[row]
            if not math.isfinite(tse):
                tse = jackknife(row)
            note = (
                ""
                if abs(e_c - stz.fit_restitution(table)) < 1e-9
                else f" Note: the critical-angle sweep is at e = {e_c:g}, the fit at e = {stz.fit_restitution(table):g}."
            )
            lines.append(
                f"θ* (μ = {mu_c:g}) = {stz.fmt_pm(ts, tse)}° against the incline's critical angle θ_c = {theta_c:g}° ± "
                f"{half:g}° (`{critical_path}`, bracket ({float(res['theta_below']):g}°, {float(res['theta_above']):g}°]): "
                f"difference {stz.fmt(ts - theta_c)}°.{note}"
            )
    return lines


# The convergence study's observables (pipelines/analysis/convergence.py keys) each section's
# comparisons use; sections absent here use none the study classes.
SECTION_OBSERVABLES = {
    "ch4": ("p", "s_over_p", "T", "p_s", "p_k"),
    "ch5": ("xi_abs", "xi_abs_ratio", "a0", "theta0", "pf_mode", "pf_zero"),
    "ch5_jamming": ("p",),
    "ch6_kinetic": ("p_s", "p_bc", "T", "C_v", "omega"),
    "ch6_network": ("z", "z@0.01", "Phi", "Phi@0.01", "Psi", "Psi@0.01", "a_c", "lhs_627", "rhs_627", "xi_abs_ratio"),
    "ch6_stz": ("s_over_p", "p", "xi_abs_ratio"),
    "ch6_d2min": ("d2min_black", "d2min_median", "d2min_largest", "d2min_jaccard"),
}
NOT_STUDIED = {
    "incline": "the incline's observables are classed against its time step by `make incline-step` "
    "(docs/results/convergence.md), not in the classes file",
}
NEAR_LIMIT = 0.02


def read_step_classes(path):
    """The rows of convergence.py --classes-csv (its comment line first)."""
    import csv

    with open(path, newline="") as fh:
        header = fh.readline().lstrip("# ").strip()
        return header, list(csv.DictReader(fh))


def step_note(step_classes, section, path):
    """One paragraph: per observable the section uses, how many of the study's state points
    class it converged, converging (and at how many the default step is within NEAR_LIMIT, or
    the errors, of the limit), regularisation-dependent or unsettled."""
    if step_classes is None:
        return []
    if section in NOT_STUDIED:
        return ["", f"**Step dependence**: {NOT_STUDIED[section]}.", ""]
    header, rows = step_classes
    parts = []
    for key in SECTION_OBSERVABLES.get(section, ()):
        mine = [r for r in rows if r["observable"] == key]
        if not mine:
            continue
        count = {c: sum(r["class"] == c for r in mine) for c in
                 ("converged", "converging", "regularisation-dependent", "unsettled")}
        near = 0
        for r in mine:
            if r["class"] != "converging":
                continue
            value, error = float(r["default_value"]), float(r["default_error"])
            limit, limit_error = float(r["limit"]), float(r["limit_error"])
            sigma = math.hypot(error if math.isfinite(error) else 0.0, limit_error if math.isfinite(limit_error) else 0.0)
            near += abs(value - limit) <= max(NEAR_LIMIT * abs(limit), sigma)
        words = []
        for c, n in count.items():
            if not n:
                continue
            words.append(f"{c} {n}")
            if c == "converging":
                words[-1] += f" (at {near} of them the default step within {NEAR_LIMIT * 100:g} % of the limit or its errors)"
        parts.append(f"{mine[0]['label']}: " + ", ".join(words))
    if not parts:
        return []
    return [
        "",
        f"**Step dependence** of the quantities above over the convergence study's {len({(r['packing_fraction'], r['restitution'], r['friction']) for r in rows})} "
        f"state points (`{path}`: {header}; classes and tables in docs/results/convergence.md): " + "; ".join(parts) + ".",
        "",
    ]


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--size", required=True)
    ap.add_argument("--output", required=True)
    ap.add_argument("--ch4-sweep", help="steady_state.py table of the ν × e sweep (Figs 4.4-4.6)")
    ap.add_argument("--ch4-bagnold", help="steady_state.py table of the Fig 4.2 runs")
    ap.add_argument("--ch4-reference", help="the Fig 4.3 run")
    ap.add_argument("--ch5-correlate", help="gf-correlate table of the chapter-5 sweep (Figs 5.2-5.10)")
    ap.add_argument("--ch5-clusters", help="gf-correlate table of the Fig 5.1 cluster windows")
    ap.add_argument("--ch5-jamming", help="jamming_point.py table (ν_c from the steady stresses)")
    ap.add_argument("--ch4-incline", help="incline_bulk.py table of the incline runs (Figs 4.8-4.10)")
    ap.add_argument("--ch4-critical", help="critical_angle.py table (θ_c)")
    ap.add_argument("--ch6-kinetic", help="gf-kinetic table of the chapter-6 runs (Figs 6.1-6.3)")
    ap.add_argument("--ch6-network", help="gf-network table of the chapter-6 runs (Figs 6.5-6.8)")
    ap.add_argument("--ch6-network-halfstep", help="gf-network table of the half-step runs and their pairs (Fig 6.7)")
    ap.add_argument("--ch6-stz", help="gf-stz fit table (Figs 6.10-6.11)")
    ap.add_argument("--ch6-d2min", help="d2min_maps.py table of the Fig. 6.9 maps")
    ap.add_argument("--step-classes", help="convergence.py --classes-csv output: each section's step dependence")
    ap.add_argument("packings", nargs="+")
    args = ap.parse_args()
    ch4 = (args.ch4_sweep, args.ch4_bagnold, args.ch4_reference)
    if any(ch4) and not all(ch4):
        ap.error("--ch4-sweep, --ch4-bagnold and --ch4-reference go together")
    if args.ch6_kinetic and not args.ch5_correlate:
        ap.error("--ch6-kinetic needs --ch5-correlate (ξ/ξ_el of its runs)")
    if args.ch6_network_halfstep and not args.ch6_network:
        ap.error("--ch6-network-halfstep needs --ch6-network")
    if bool(args.ch4_incline) != bool(args.ch4_critical):
        ap.error("--ch4-incline and --ch4-critical go together")
    lines = [
        f"# granflow reproduction report (SIZE={args.size})",
        "",
        "Generated by `make -f Makefile.sweeps`; every number below is read from the run files named.",
        "",
        "## Packings (thesis App. A.3)",
        "",
        "| file | N | target ν | achieved ν | max overlap / σ | seed |",
        "|---|---|---|---|---|---|",
    ]
    for name, n, nu, got, ov, seed in packing_rows(args.packings):
        lines.append(f"| {name} | {n} | {nu:.3f} | {got:.12f} | {ov:.2e} | {seed} |")
    classes = read_step_classes(args.step_classes) if args.step_classes else None

    def section(name, body):
        return body + step_note(classes, name, args.step_classes)

    if all(ch4):
        lines += section("ch4", ch4_section(*ch4))
    if args.ch4_incline:
        lines += section("incline", incline_section(args.ch4_incline, args.ch4_critical, args.ch4_sweep))
    if args.ch5_correlate:
        lines += section("ch5", ch5_section(args.ch5_correlate, args.ch5_clusters))
    if args.ch5_jamming:
        lines += section("ch5_jamming", ch5_jamming_section(args.ch5_jamming))
    if args.ch6_kinetic:
        lines += section("ch6_kinetic", ch6_section(args.ch6_kinetic, args.ch5_correlate))
    if args.ch6_network:
        lines += section("ch6_network", ch6_network_section(args.ch6_network, args.ch6_network_halfstep))
    if args.ch6_d2min:
        lines += section("ch6_d2min", ch6_d2min_section(args.ch6_d2min))
    if args.ch6_stz:
        lines += section("ch6_stz", ch6_stz_section(args.ch6_stz, args.ch4_critical))
    write_text(args.output, "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
