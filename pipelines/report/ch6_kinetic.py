"""Chapter 6, kinetic theory (thesis §6.1, Figs 6.1–6.3): gf-kinetic's stresses and predictions,
with gf-correlate's ξ/ξ_el, beside the thesis' statements (every number from the tables; "not
measured" where a dataset is NaN)."""
import numpy as np

from granflow import correlation_table as ct
from granflow import kinetic_table as kt
from report.render import head, quote


class Kinetic:
    """The kinetic table with what every part of the section reads from it: ξ/ξ_el per run (and
    whether it is above the open-point threshold), ν, the μ = 0 rows and their e, largest first."""

    def __init__(self, kinetic_path, correlate_path):
        self.path = kinetic_path
        self.table = table = kt.read_table(kinetic_path)
        self.ratio, _, measurable = kt.xi_ratio(table, ct.read_table(correlate_path))
        self.full = kt.filled(self.ratio, measurable)
        self.nu = kt.column(table, "packing_fraction")
        self.baseline = float(table["runs"]["attrs"].get("velocity_correlation_baseline", -0.25))
        self.frictionless = np.abs(kt.column(table, "friction")) < 1e-9
        self.es = sorted({float(e) for e in kt.column(table, "restitution")[self.frictionless]}, reverse=True)

    def rows(self, e):
        """The μ = 0 rows at restitution e."""
        rows = kt.select(self.table, e)
        return rows[self.frictionless[rows]]

    def open_rows(self, e):
        """The open points at e: μ = 0 runs with a ξ/ξ_el at most the threshold."""
        rows = self.rows(e)
        return rows[~self.full[rows] & np.isfinite(self.ratio[rows])]


def intro(k, correlate_path):
    """The table, where χ comes from, and the conventions of the comparisons."""
    runs, attrs, eq, nu = k.table["runs"], k.table["runs"]["attrs"], k.table.get("equilibrium"), k.nu
    chi_source = np.asarray(runs.get("chi_source", np.full(len(nu), -1)), dtype=int)
    return [
        "",
        "## Chapter 6: kinetic theory (thesis §6.1, Figs 6.1–6.3)",
        "",
        f"Table `{k.path}` (gf-kinetic, one row per run): {len(nu)} runs, N = {int(np.max(runs['grains']))}"
        + (
            f", χ interpolated from {len(eq['packing_fraction'])} equilibrium runs (e = 1, γ̇ = 0) at ν = "
            + ", ".join(f"{v:.3f}" for v in eq["packing_fraction"])
            if eq is not None
            else ", no equilibrium runs: χ from Henderson's formula"
        )
        + f" ({int(np.sum(chi_source == 1))} runs extrapolated, {int(np.sum(chi_source == 2))} from Henderson's "
        f"formula). ξ/ξ_el from `{correlate_path}` (gf-correlate's ξ_|C|, matched by run path; "
        f"{int(np.sum(np.isfinite(k.ratio)))} of {len(nu)} runs found there). “Agree within errors”: "
        f"|a − b| ≤ {kt.AGREE_SIGMAS:g} combined blocked standard errors. Velocity correlation convention: "
        f"{attrs.get('velocity_correlation_convention', 'not stated')}, molecular-chaos baseline {k.baseline:g}.",
        "",
    ]


def equilibrium_lines(eq):
    """The equilibrium runs' drifts and χ three ways (none: no lines)."""
    if eq is None:
        return []
    lines = [
        "Equilibrium runs (χ from the collision frequency, ω = √(2π T) χ n σ, beside the virial estimate "
        "and Henderson's formula):",
        "",
        *head("ν", "energy drift", "T drift", "χ (collisions)", "χ (virial)", "χ Henderson"),
    ]
    for i in range(len(eq["packing_fraction"])):
        g = lambda name: float(eq[name][i]) if name in eq else kt.NAN  # noqa: E731
        lines.append(
            f"| {g('packing_fraction'):.3f} | {kt.fmt_percent(g('energy_drift'))} | "
            f"{kt.fmt_percent(g('temperature_drift'))} | "
            f"{kt.fmt_pm(g('chi'), g('chi_error'))} | {kt.fmt_pm(g('chi_virial'), g('chi_virial_error'))} | "
            f"{kt.fmt_ratio(g('chi_henderson'))} |"
        )
    return lines + [""]


def dilute_regime(k, e):
    """Per e (μ = 0): the ν range where p^bc = p^s and where it agrees again, the ν up to which the
    Enskog pressure holds, its ratio at the most dilute ν, and the last open point (None if none)."""
    rows = k.rows(e)
    upto, again = kt.dilute_range(k.nu[rows], kt.pressures_agree(k.table, rows))
    holds, pratio = kt.pressure_prediction_holds(k.table, rows)
    pupto, _ = kt.dilute_range(k.nu[rows], holds)
    open_rows = k.open_rows(e)
    return {
        "rows": rows, "upto": upto, "again": again, "pupto": pupto, "pratio": pratio[0],
        "last_open": np.max(k.nu[open_rows]) if len(open_rows) else None,
    }


def pressure_lines(k):
    """The binary-collision range and the pressure prediction, per e."""
    lines = [
        quote("binary_regime"),
        quote("pressure_prediction"),
        "Per e (μ = 0): the ν range, from the most dilute run on, where p^bc = p^s within errors; the largest ν "
        f"up to which the Enskog pressure holds within {100 * kt.PRESSURE_TOLERANCE:g} % (|p^s/(p⁰(1+e)χν) − 1|, "
        "eq. 6.9); the largest ν with ξ/ξ_el ≤ 1.25 (open points of the figures).",
        "",
        *head("e", "runs", "ν range p^bc = p^s", "agree again at", "p^s/p_enskog within 5 % up to",
              "p^s/p_enskog at the most dilute ν", "last open point (ξ/ξ_el ≤ 1.25)"),
    ]
    for e in k.es:
        if len(k.rows(e)) == 0:
            continue
        d = dilute_regime(k, e)
        rows, upto = d["rows"], d["upto"]
        lines.append(
            f"| {e:g} | {len(rows)} | "
            + (f"{k.nu[rows][0]:.3f}–{upto:.3f}" if np.isfinite(upto) else "none (differ at the most dilute ν)")
            + f" | {', '.join(f'{v:.3f}' for v in d['again']) or '–'} | {kt.fmt_nu(d['pupto'])} | "
            f"{kt.fmt_ratio(d['pratio'])} | {'none' if d['last_open'] is None else kt.fmt_nu(d['last_open'])} |"
        )
    return lines


def shear_prediction_lines(k):
    """Which shear-stress prediction the dilute e = 0.92 data follow."""
    lines = ["", quote("shear_prediction")]
    high = k.rows(0.92)
    if not len(high):
        return lines + ["Ours: no run at e = 0.92: not measured."]
    r, col = high[0], lambda name: kt.column(k.table, name)
    s_thesis = col("s_static")[r] / col("s_enskog_thesis")[r]
    s_2d = col("s_static")[r] / col("s_enskog_2d")[r]
    lines.append(
        f"Ours, e = 0.92 at the most dilute ν = {k.nu[r]:.3f}: s^s/s_pred = {kt.fmt_ratio(s_thesis)} for eq. 6.10 "
        f"as printed, {kt.fmt_ratio(s_2d)} for the 2D Garzó–Dufty viscosity "
        f"(s^s = {kt.fmt_pm(col('s_static')[r], col('s_static_error')[r])}): "
        f"the data follow **{kt.closer_prediction(s_thesis, s_2d)}** more closely."
    )
    return lines


def velocity_correlations(k):
    """Per open point: (e, row, C_v's sign against the baseline, the relative shear-stress errors of
    eq. 6.10 and of the 2D viscosity)."""
    cv, cv_err = kt.column(k.table, "velocity_correlation"), kt.column(k.table, "velocity_correlation_error")
    out = []
    for e in k.es:
        rows = k.open_rows(e)
        err_thesis = kt.shear_error(k.table, rows, "s_enskog_thesis")
        err_2d = kt.shear_error(k.table, rows, "s_enskog_2d")
        for i, r in enumerate(rows):
            out.append((e, r, kt.sign_word(cv[r], cv_err[r], k.baseline), err_thesis[i], err_2d[i]))
    return out


def proportionality(k, points):
    """The signs of C_v − baseline counted, and Pearson's r of C_v − baseline against each
    prediction's relative shear-stress error, over the velocity_correlations() points."""
    cv = kt.column(k.table, "velocity_correlation")
    excess = np.array([cv[r] - k.baseline for _, r, _, _, _ in points])
    signs = np.array([sign for _, _, sign, _, _ in points])
    r_thesis, n_thesis = kt.proportionality(excess, np.array([p[3] for p in points]))
    r_2d, n_2d = kt.proportionality(excess, np.array([p[4] for p in points]))
    counts = {w: int(np.sum(signs == w)) for w in ("positive", "negative", "zero within errors", "not measured")}
    return counts, (r_thesis, n_thesis), (r_2d, n_2d)


def velocity_correlation_lines(k):
    """C_v beside the shear-stress error, on the open points."""
    cv, cv_err = kt.column(k.table, "velocity_correlation"), kt.column(k.table, "velocity_correlation_error")
    lines = [
        "",
        quote("velocity_correlation"),
        f"Ours, on the open points (ξ/ξ_el ≤ 1.25), per e: C_v and its sign against the molecular-chaos "
        f"baseline {k.baseline:g} (and against 0, the sign the thesis reads), and the relative shear-stress "
        "error (s_pred − s^s)/s^s of both predictions at the same runs:",
        "",
        *head("e", "ν", "C_v", "C_v − baseline", "sign vs baseline", "sign vs 0", "(s_6.10 − s^s)/s^s",
              "(s_2D − s^s)/s^s"),
    ]
    points = velocity_correlations(k)
    for e, r, sign, err_thesis, err_2d in points:
        lines.append(
            f"| {e:g} | {k.nu[r]:.3f} | {kt.fmt_pm(cv[r], cv_err[r])} | {kt.fmt_pm(cv[r] - k.baseline, cv_err[r])} | "
            f"{sign} | {kt.sign_word(cv[r], cv_err[r])} | {kt.fmt_ratio(err_thesis)} | {kt.fmt_ratio(err_2d)} |"
        )
    if not points:
        return lines + ["", "No open points with a ξ/ξ_el: not measured."]
    counts, (r_thesis, n_thesis), (r_2d, n_2d) = proportionality(k, points)
    return lines + [
        "",
        f"Over the {len(points)} open points: C_v − baseline is positive in {counts['positive']}, negative in "
        f"{counts['negative']}, zero within errors in {counts['zero within errors']}, not measured in "
        f"{counts['not measured']}. Pearson's r between C_v − baseline and the relative shear-stress error: "
        f"{kt.fmt_ratio(r_thesis)} for eq. 6.10 as printed ({n_thesis} points), {kt.fmt_ratio(r_2d)} for "
        f"2D Garzó–Dufty ({n_2d} points) (r near 1: the thesis' “roughly proportional”).",
    ]


def section(kinetic_path, correlate_path):
    """Chapter 6, kinetic theory: gf-kinetic's stresses and predictions beside thesis §6.1."""
    k = Kinetic(kinetic_path, correlate_path)
    return (
        intro(k, correlate_path)
        + equilibrium_lines(k.table.get("equilibrium"))
        + pressure_lines(k)
        + shear_prediction_lines(k)
        + velocity_correlation_lines(k)
    )
