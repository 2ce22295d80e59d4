"""Chapter 6, the force-network model (thesis §6.2, Figs 6.5–6.8): gf-network's Φ, Ψ, z, Fourier
components and both sides of eqs. 6.27–6.29 beside the thesis' statements (every number from the
tables; "not measured" where a dataset is NaN)."""
import numpy as np

from granflow import network_table as nt
from report.render import head, quote


def where(table, r):
    """A run named by its ν and e."""
    return f"ν = {nt.column(table, 'packing_fraction')[r]:.3f}, e = {nt.column(table, 'restitution')[r]:g}"


def intro(table, network_path):
    """The table, what z, Φ and Ψ count, and where ξ/ξ_el comes from."""
    n = nt.rows(table)
    xi_source = table["prediction"]["attrs"].get("xi_source", "correlation")
    return [
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


def phi_lines(table):
    """Φ's range over the runs and in how many Ψ < Φ."""
    phi, phi_err = nt.column(table, "Phi"), nt.column(table, "Phi_error")
    lo, hi = nt.value_range(phi)
    below, finite, exceptions = nt.psi_below_phi(table)
    lines = [quote("phi_constant"), quote("psi_below_phi")]
    if not finite:
        return lines + ["Ours: Φ and Ψ not measured (no run with pairs of long-lived contacts)."]
    rlo, rhi = int(np.nanargmin(phi)), int(np.nanargmax(phi))
    lines.append(
        f"Ours: Φ from {nt.fmt_pm(phi[rlo], phi_err[rlo])} ({where(table, rlo)}) to "
        f"{nt.fmt_pm(phi[rhi], phi_err[rhi])} ({where(table, rhi)}) over {finite} runs (range {lo:.3f}–{hi:.3f}, "
        f"thesis ≈ {nt.THESIS_PHI:g}); Ψ < Φ in {below} of {finite} runs"
        + (f" (not at {'; '.join(where(table, r) for r in exceptions)})." if len(exceptions) else ".")
    )
    return lines


def fourier_lines(table):
    """The 4θ Fourier components of C(θ) and F_bc(θ) against the thesis' bound, and the largest
    first-order component."""
    parts = []
    for names, what in ((("a4_c", "a4_c_prime"), "C(θ)"), (("a4_f", "a4_f_prime"), "F_bc(θ)")):
        value, error, name, row = nt.largest_abs(table, names)
        large, counted = nt.count_at_least(table, names, nt.THESIS_NEXT_ORDER)
        if name is None:
            parts.append(f"the 4θ components of {what} not measured")
        else:
            parts.append(
                f"the largest 4θ component of {what} is {name} = {nt.fmt_pm(value, error)} ({where(table, row)}); "
                f"{large} of {counted} runs have a 4θ component of {what} with |value| ≥ {nt.THESIS_NEXT_ORDER:g}"
            )
    value, error, name, row = nt.largest_abs(table, ("a_c", "a_c_prime", "a_f", "a_f_prime"))
    return [
        "",
        quote("next_order"),
        "Ours: "
        + "; ".join(parts)
        + ". The largest first-order component: "
        + (f"{name} = {nt.fmt_pm(value, error)} ({where(table, row)})." if name else "not measured."),
    ]


def z_steps(half, pairs):
    """z at the default step and at half of it, over the pairs (default, half) of nt.step_pairs:
    z's difference of each pair in combined errors, the pair of the largest (None if none is
    finite) and how many agree within errors."""
    z, dz = nt.column(half, "coordination"), nt.column(half, "coordination_error")
    diffs = [float(nt.difference_sigmas(z[j], dz[j], z[i], dz[i])) for i, j in pairs]
    agree = sum(1 for d in diffs if np.isfinite(d) and abs(d) <= nt.AGREE_SIGMAS)
    return diffs, nt.largest_finite(diffs), agree


def halfstep_lines(halfstep_path):
    """z against the time step (the inset of Fig 6.7), from the half-step table if there is one."""
    lines = ["", quote("z_time_step")]
    if not halfstep_path:
        return lines + ["Ours: no half-step runs: not measured."]
    half = nt.read_table(halfstep_path)
    pairs = nt.step_pairs(half)
    if not pairs:
        return lines + [f"Ours: `{halfstep_path}` has no pair of runs with equal ν, e and dt ratio 2: not measured."]
    diffs, k, agree = z_steps(half, pairs)
    z, dz = nt.column(half, "coordination"), nt.column(half, "coordination_error")
    hnu, he = nt.column(half, "packing_fraction"), nt.column(half, "restitution")
    lines += head("ν", "e", "z (default step)", "z (half step)", "difference")
    for (i, j), d in zip(pairs, diffs):
        lines.append(
            f"| {hnu[i]:.3f} | {he[i]:g} | {nt.fmt_pm(z[i], dz[i])} | {nt.fmt_pm(z[j], dz[j])} | {nt.fmt_sigmas(d)} |"
        )
    return lines + [
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


def collapse_lines(table):
    """Fig 6.8: how well log lhs against log rhs of eqs. 6.27–6.29 collapse onto slope 1, per reading."""
    lines = [
        "",
        quote("collapse"),
        "Ours: log10 lhs against log10 rhs over the runs with both sides positive (a perfect collapse: slope 1, "
        "scatter 0). Scatter = rms of log10(lhs/rhs) in decades (dex); decades = the span of log10 rhs (of log10 "
        "lhs in brackets) over those runs; rows left out because a side is ≤ 0, or without a value (no ξ/ξ_el). "
        "Readings: " + "; ".join(f"{r[1:] or 'main'} = {text}" for r, text in nt.READINGS) + ".",
        "",
        *head("eq.", "reading", "slope", "scatter (dex)", "runs used", "side ≤ 0", "no value", "decades rhs (lhs)"),
    ]
    for c in nt.collapse_table(table):
        lines.append(
            f"| {c['number']} | {c['reading'][1:] or 'main'} | {nt.fmt_number(c['slope'])} | "
            f"{nt.fmt_number(c['scatter'])} | {c['used']} | {c['non_positive']} | {c['missing']} | "
            f"{nt.fmt_number(c['decades_rhs'], 2)} ({nt.fmt_number(c['decades_lhs'], 2)}) |"
        )
    return lines


def continuation_lines(table):
    """Only a run with a sum limit can lack a real continuation of the sums: how many do."""
    real = nt.column(table, "continuation_real", "prediction")
    limited = np.isfinite(nt.column(table, "sum_limit", "prediction"))
    return [
        "",
        f"{int(np.sum(limited & (real == 0)))} of {int(np.sum(limited))} runs with a ξ/ξ_el have a negative base "
        "with a non-integer ξ/ξ_el − 1 (no real continuation of the sums: their main reading is the floor one).",
    ]


def bound_lines(table):
    """Eq. 6.27's bound, whatever the reading: the measured excess against ξ/ξ_el − 1."""
    excess = nt.bound_excess(table)
    measured = np.isfinite(excess)
    above = measured & (excess > nt.AGREE_SIGMAS)
    kb = nt.largest_finite(np.where(measured, excess, np.nan))
    col = lambda name: nt.column(table, name, "prediction")  # noqa: E731
    return [
        "",
        "With 0 ≤ min[Φ(z − 1), 1] ≤ 1 the right-hand side of eq. 6.27 is at most ξ/ξ_el − 1 (every link passes "
        "its whole force on), whatever z, Φ and the reading of the sums. Ours: (p^s − p^bc)/p^bc exceeds ξ/ξ_el − 1 "
        f"by more than {nt.AGREE_SIGMAS:g} combined errors in {int(above.sum())} of {int(measured.sum())} runs with "
        "a ξ/ξ_el"
        + (
            f" (largest: {where(table, kb)}, {nt.fmt_pm(col('lhs_pressure')[kb], col('lhs_pressure_error')[kb])} "
            f"against ξ/ξ_el − 1 = {nt.fmt_number(col('sum_limit')[kb], 2)})."
            if kb is not None
            else "."
        ),
    ]


def identity_lines(table):
    """σ(θ)'s anisotropy and the identity s^bc/p^bc = −2χ12, from the stress rows and the frames."""
    ratio, ratio_err, target, target_err, sig = nt.identity_deviation(table)
    frames = nt.identity_deviation(table, frames=True)
    aniso = nt.value_range(nt.column(table, "sigma_anisotropy"))
    maxdev = nt.value_range(nt.column(table, "sigma_max_deviation"))
    k, kf = nt.largest_finite(sig), nt.largest_finite(frames[4])
    return [
        "",
        "The identity s^bc/p^bc = −2χ12 (s = −Σxy) holds when the contact distance σ(θ) does not depend on θ. "
        f"Ours: the 2θ amplitude of σ(θ)/⟨σ⟩ from {nt.fmt_number(aniso[0], 4)} to {nt.fmt_number(aniso[1], 4)}, "
        f"the largest |σ_k/⟨σ⟩ − 1| of a θ bin from {nt.fmt_number(maxdev[0], 4)} to {nt.fmt_number(maxdev[1], 4)}. "
        "s^bc/p^bc from the stress rows against −2χ12: "
        + (
            f"largest difference {nt.fmt_sigmas(sig[k])} ({where(table, k)}: {nt.fmt_pm(ratio[k], ratio_err[k])} "
            f"against {nt.fmt_pm(target[k], target_err[k])}), within errors in "
            f"{int(np.sum(np.abs(sig[np.isfinite(sig)]) <= nt.AGREE_SIGMAS))} of {int(np.sum(np.isfinite(sig)))} runs"
            if k is not None
            else "not measured"
        )
        + "; from the frames' contacts (exact whatever σ(θ)): "
        + (
            f"largest difference {nt.fmt_sigmas(frames[4][kf])} ({where(table, kf)})."
            if kf is not None
            else "not measured."
        ),
    ]


def section(network_path, halfstep_path=None):
    """Chapter 6, the force-network model, beside the statements of thesis §6.2."""
    table = nt.read_table(network_path)
    return (
        intro(table, network_path)
        + phi_lines(table)
        + fourier_lines(table)
        + halfstep_lines(halfstep_path)
        + collapse_lines(table)
        + continuation_lines(table)
        + bound_lines(table)
        + identity_lines(table)
    )
