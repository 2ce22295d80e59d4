"""Chapter 4, simple shear (thesis §4.2.2, Figs 4.1–4.6): steady_state.py's tables of the ν × e sweep
and of the Bagnold runs, and the reference run, beside the thesis' statements."""
import os

import numpy as np

from analysis import steady_state as ss
from report.render import fmt, head, quote, sigmas, subsection

# Fig 4.3's invariants and Fig 4.2's scaled quantities: (table column, label).
INVARIANTS = (("s_over_p", "s/p"), ("rate_R_over_sqrt_T", "γ̇⟨R⟩/√T"), ("mT_over_pR2", "mT/(p⟨R⟩²)"))
SCALED = (
    ("pressure_scaled", "p/(γ̇²m)"),
    ("shear_stress_scaled", "s/(γ̇²m)"),
    ("temperature_scaled", "T/(γ̇²⟨R⟩²)"),
)
# Figs 4.4 and 4.5's columns, after ν and the start of the steady part.
RHEOLOGY = (
    "pressure_scaled",
    "shear_stress_scaled",
    "temperature_scaled",
    "s_over_p",
    "normal_stress_difference",
    "pressure_static_scaled",
    "pressure_kinetic_scaled",
)


def cell(table, name, row):
    """A steady value of a steady_state.py table with its error and marks."""
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


def intro(sweep, sweep_path, bagnold_path):
    """The tables, the run length, the errors, the largest overlap and the solver's iterations."""
    runs = sweep["runs"]
    overlap = sweep["diagnostics"]["max_overlap_max"] / (2 * runs["mean_radius"])
    worst = int(np.argmax(overlap))
    iterations = sweep["diagnostics"]["solver_iterations_mean"]
    return [
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
        f"{iterations.min():.3g}–{iterations.max():.3g}.",
        "",
    ]


def bagnold_lines(bagnold):
    """Fig 4.2: the scaled stresses and temperature at each rate, and the change across the rates."""
    runs, st = bagnold["runs"], bagnold["steady"]
    rows = np.argsort(runs["rate"])
    lines = [
        "### Bagnold scaling (Fig 4.2)",
        "",
        quote("bagnold_pressure"),
        quote("bagnold_invariance"),
        f"Ours, ν = {runs['packing_fraction'][rows[0]]:.3f}, e = {runs['restitution'][rows[0]]:g}, "
        f"μ = {runs['friction'][rows[0]]:g}, same packing and strain step (dt ∝ 1/γ̇):",
        "",
        *head("quantity", *(f"γ̇ = {r:g}" for r in runs["rate"][rows]), "(last − first)/σ"),
    ]
    a, b = rows[0], rows[-1]
    for name, label in SCALED:
        change = sigmas(st[name][b] - st[name][a], st[name + "_error"][a], st[name + "_error"][b])
        lines.append(f"| {label} | " + " | ".join(cell(bagnold, name, r) for r in rows) + f" | {change} |")
    return lines


def transient(run, from_strain):
    """Fig 4.3's check on a run, from the strain its steady part starts at: the steady means of
    the invariants over the two halves of that part, and each one's relative fluctuation."""
    end = float(run["series"]["strain"][-1])
    middle = 0.5 * (from_strain + end)
    first, second = ss.steady_values(run, from_strain, middle)[0], ss.steady_values(run, middle)[0]
    inst = ss.invariant_series(run)
    steady = run["series"]["strain"] >= from_strain
    fluctuation = {}
    for name, _ in INVARIANTS:
        x = inst[name][steady]
        fluctuation[name] = np.nanstd(x) / abs(np.nanmean(x))
    return {"middle": middle, "end": end, "first": first, "second": second, "fluctuation": fluctuation}


def transient_lines(check, from_strain, reference_path):
    """Fig 4.3: the transient() check of the reference run."""
    middle, end = check["middle"], check["end"]
    lines = [
        *subsection("Steady state and fluctuations (Fig 4.3)", "steady_reached", "fluctuations"),
        f"Ours (`{os.path.basename(reference_path)}`): the steady part split in two halves — equal means "
        "(|difference| of a few σ at most) say the transient is over by strain "
        f"{from_strain:g}; relative fluctuation = standard deviation / mean of the per-step values.",
        "",
        *head("invariant", f"strain {from_strain:g}–{middle:.3g}", f"{middle:.3g}–{end:.3g}", "difference/σ",
              "relative fluctuation"),
    ]
    for name, label in INVARIANTS:
        (a, ea, pa), (b, eb, pb) = check["first"][name], check["second"][name]
        lines.append(
            f"| {label} | {fmt(a, ea, pa)} | {fmt(b, eb, pb)} | {sigmas(b - a, ea, eb)} "
            f"| {check['fluctuation'][name]:.3g} |"
        )
    return lines


def pressure_parts(sweep):
    """|N₁| over every μ = 0 run, and the ν at e = 0, μ = 0 where the static pressure exceeds the
    kinetic one and where it does not."""
    runs, st = sweep["runs"], sweep["steady"]
    zero = ss.select(sweep, restitution=0.0, friction=0.0)
    n1 = np.abs(st["normal_stress_difference"][ss.select(sweep, friction=0.0)])
    static_wins = [runs["packing_fraction"][r] for r in zero if st["pressure_static"][r] > st["pressure_kinetic"][r]]
    kinetic_wins = [runs["packing_fraction"][r] for r in zero if st["pressure_static"][r] <= st["pressure_kinetic"][r]]
    return n1, static_wins, kinetic_wins


def rheology_lines(sweep):
    """Figs 4.4 and 4.5: the steady rheology against ν at e = 0, μ = 0, N₁ and the pressure's parts."""
    runs = sweep["runs"]
    lines = [
        *subsection(
            "Steady rheology against ν, e = 0, μ = 0 (Figs 4.4, 4.5)",
            "dense_increase", "stress_diverges", "n1_previous", "static_over_kinetic",
        ),
        *head("ν", "steady from", "p/(γ̇²m)", "s/(γ̇²m)", "T/(γ̇²⟨R⟩²)", "s/p", "N₁", "pˢ/(γ̇²m)", "pᵏ/(γ̇²m)"),
    ]
    for r in ss.select(sweep, restitution=0.0, friction=0.0):
        start = f"{runs['steady_from'][r]:.3g} of {runs['strain'][r]:g}" if "steady_from" in runs else "–"
        lines.append(
            f"| {runs['packing_fraction'][r]:.3f} | {start} | "
            + " | ".join(cell(sweep, name, r) for name in RHEOLOGY)
            + " |"
        )
    n1, static_wins, kinetic_wins = pressure_parts(sweep)
    lines += [
        "",
        f"Ours: |N₁| = {n1.min():.2g}–{n1.max():.2g} over all {len(n1)} μ = 0 runs of the sweep (every e). "
        f"pˢ > pᵏ at ν = {', '.join(f'{v:.3f}' for v in static_wins) or 'none'}; "
        f"pˢ ≤ pᵏ at ν = {', '.join(f'{v:.3f}' for v in kinetic_wins) or 'none'}.",
    ]
    return lines


def static_pressure(sweep):
    """Fig 4.6's check: per ν, the μ = 0 rows at each e (None where the sweep has none) and the
    ratio of the largest static pressure to the smallest over e (None with fewer than two)."""
    runs, st = sweep["runs"], sweep["steady"]
    frictionless = ss.select(sweep, friction=0.0)
    es = np.unique(runs["restitution"][frictionless])
    out = []
    for nu in np.unique(runs["packing_fraction"][frictionless]):
        rows, values = [], []
        for e in es:
            r = ss.select(sweep, friction=0.0, restitution=e, packing_fraction=nu)
            rows.append(r[0] if len(r) else None)
            values += [st["pressure_static_scaled"][r[0]]] if len(r) else []
        out.append((nu, rows, max(values) / min(values) if len(values) > 1 else None))
    return es, out


def static_pressure_lines(sweep):
    """Fig 4.6: the static pressure against ν for every e at μ = 0."""
    es, rows = static_pressure(sweep)
    lines = [
        *subsection("Static pressure for several e, μ = 0 (Fig 4.6)", "pressure_independent_of_e", "variance_with_e"),
        *head("ν", *(f"pˢ/(γ̇²m), e = {e:g}" for e in es), "max/min over e"),
    ]
    for nu, at_e, ratio in rows:
        cells = [cell(sweep, "pressure_static_scaled", r) if r is not None else "–" for r in at_e]
        lines.append(f"| {nu:.3f} | " + " | ".join(cells) + f" | {'–' if ratio is None else f'{ratio:.3g}'} |")
    return lines


def section(sweep_path, bagnold_path, reference_path):
    """Chapter 4: steady simple shear beside the statements of thesis §4.2.2."""
    sweep, bagnold = ss.read_table(sweep_path), ss.read_table(bagnold_path)
    run = ss.read_run(reference_path)
    # Fig 4.3 from where the tables start the run's steady part.
    from_strain = ss.steady_start(
        run, float(sweep["parameters"]["from_strain"]), int(bagnold["parameters"].get("detect_transient", 0))
    )
    return (
        intro(sweep, sweep_path, bagnold_path)
        + bagnold_lines(bagnold)
        + transient_lines(transient(run, from_strain), from_strain, reference_path)
        + rheology_lines(sweep)
        + static_pressure_lines(sweep)
    )
