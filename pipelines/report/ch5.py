"""Chapter 5, microstructure (thesis §5.1–5.3, Figs 5.1–5.10): gf-correlate's tables (force
correlations, ξ, P(f), ν_bc, anisotropy, clusters) and jamming_point.py's ν_c beside the thesis'
statements."""
import math
import os

import numpy as np

from analysis import jamming_point
from granflow import correlation_table as ct
from granflow import outputs
from report.render import head, quote, subsection

# gf-correlate's ν_bc status codes (/sweep/status).
STATUS_NAMES = {0: "bracketed", 1: "all_above", 2: "all_below", 3: "too_few", 4: "only_downward"}


def intro(table, res, correlate_path):
    """The table, its frames and lags, which ξ the section uses, and ξ_el."""
    runs, cor = table["runs"], table["correlation"]
    sigma = ct.mean_diameter(table)
    return [
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
        quote("xi_dilute_limit"),
        f"Ours: ξ_el = {ct.fmt_pm(res['xi_el'] / sigma, res['xi_el_error'] / sigma)}σ from "
        + ", ".join(f"`{os.path.basename(runs['input'][r])}`" for r in res["reference_rows"])
        + " (C̄ is a density per unit area, so isolated contacts give ξ ≈ the contact distance ≈ σ; "
        "only ξ/ξ_el compares with the thesis).",
        "",
    ]


def xi_cell(table, res, r):
    """ξ/ξ_el of a run with its marks: † not measurable, ▲/○ P(f)'s peak, and a low confidence."""
    fo = table["forces"]
    mark = "▲" if fo["peak"][r] == 1 else "○"
    conf = fo["peak_confidence"][r]
    return (
        f"{ct.fmt_pm(res['ratio'][r], res['ratio_error'][r])}{'' if res['measurable'][r] else ' †'} "
        f"{mark}" + (f" ({100 * conf:.0f} %)" if conf < 0.8 else "")
    )


def xi_lines(table, res, es, nus):
    """ξ/ξ_el against ν and e at μ = 0, with P(f)'s peak or its absence."""
    lines = [
        quote("xi_grows"),
        quote("pf_peak"),
        "ξ_|C|/ξ_el for μ = 0; ▲ = gf-correlate finds a peak of P(f) at f > 0, ○ = maximum at f = 0 "
        "(bootstrap confidence < 80 % in brackets); † = correlations reach the box (more than "
        f"{100 * res['max_tail_share']:g} % of ∫ℓ|C| beyond 2ℓ_max/3): not measurable, left out below:",
        "",
        *head("ν", *(f"e = {e:g}" for e in es)),
    ]
    for nu in nus:
        cells = []
        for e in es:
            r = ct.select(table, restitution=e, friction=0.0, packing_fraction=nu)
            cells.append(xi_cell(table, res, r[0]) if len(r) else "–")
        lines.append(f"| {nu:.3f} | " + " | ".join(cells) + " |")
    return lines


def trends(table, res, es, nus):
    """The statements of l. 553, 555 and 645 on the measurable μ = 0 runs: the deviation of ξ/ξ_el
    from 1 at the lowest ν per e, how often ξ grows with ν and falls with e, and how the P(f) peak
    splits at the threshold."""
    runs, fo = table["runs"], table["forces"]
    ok = res["measurable"]
    low_rows = ct.select(table, friction=0.0, packing_fraction=nus[0])
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
    frictionless = ct.select(table, friction=0.0)
    used = frictionless[ok[frictionless]]
    ratio, peak = res["ratio"][used], fo["peak"][used]
    dense, dilute = ratio >= res["threshold"], ratio < res["threshold"]
    return {
        "dev": dev, "rising": rising, "steps": steps, "ordered": ordered, "pairs": pairs,
        "dense": int(dense.sum()), "dense_at_zero": int((peak[dense] == 0).sum()),
        "dilute": int(dilute.sum()), "dilute_peaked": int((peak[dilute] == 1).sum()),
    }


def trend_lines(t, low, thr):
    """The trends() check in words."""
    return [
        "",
        f"Ours: at the lowest ν = {low:.3f}, (ξ/ξ_el − 1)/error = "
        + ", ".join(f"{d:+.1f} (e = {e:g})" for e, d in t["dev"])
        + f". Over the measurable runs, ξ grows with ν in {t['rising']} of {t['steps']} consecutive steps (all e) "
        f"and decreases with e in {t['ordered']} of {t['pairs']} neighbouring pairs at fixed ν. P(f): of the "
        f"{t['dense']} runs with ξ/ξ_el ≥ {thr:g}, {t['dense_at_zero']} have their maximum "
        f"at f = 0; of the {t['dilute']} runs with ξ/ξ_el < {thr:g}, {t['dilute_peaked']} "
        "have a peak at f > 0 (the thesis: all of them). Where the peak goes, per e, is in the next table.",
        "",
    ]


def gf_nu_bc(sweep, s):
    """gf-correlate's own ν_bc of a series (signed ξ), or its status, or – without a sweep row."""
    if not sweep:
        return "–"
    k = np.flatnonzero(
        (np.abs(sweep["restitution"] - s["restitution"]) < 1e-6) & (np.abs(sweep["friction"] - s["friction"]) < 1e-6)
    )
    if not len(k):
        return "–"
    k = k[0]
    if sweep["status"][k] == 0:
        return ct.fmt_pm(sweep["nu_bc"][k], sweep["nu_bc_error"][k])
    return STATUS_NAMES.get(int(sweep["status"][k]), "?")


def peak_gone(table, s):
    """The lowest ν from which every run of a series has its P(f) maximum at f = 0 (None: never)."""
    rows = ct.select(table, restitution=s["restitution"], friction=s["friction"])
    peaks = table["forces"]["peak"][rows]
    gone = [table["runs"]["packing_fraction"][rows][i] for i in range(len(peaks)) if (peaks[i:] == 0).all()]
    return gone[0] if gone else None


def nu_bc_lines(table, res):
    """ν_bc per (e, μ) series beside gf-correlate's and where P(f)'s peak goes."""
    sweep = table.get("sweep", {})
    lines = [
        quote("nu_bc_friction"),
        "Peak gone from ν: the lowest ν from which every run of the series has its P(f) maximum at f = 0.",
        "",
        *head("e", "μ", "runs", "ν_bc (ξ_|C|)", "status", "ν_bc (gf-correlate, signed ξ)", "P(f) peak gone from ν"),
    ]
    for s in res["series"]:
        gone = peak_gone(table, s)
        lines.append(
            f"| {s['restitution']:g} | {s['friction']:g} | {s['runs']} | "
            f"{ct.fmt_pm(s['nu_bc'], s['nu_bc_error']) if s['status'] == 'bracketed' else '–'} | "
            f"{s['status']} | {gf_nu_bc(sweep, s)} | {'never' if gone is None else f'{gone:.3f}'} |"
        )
    return lines


def anisotropy_signed(table, res, frictionless):
    """Eq. 5.3 pooled over the μ = 0 runs with a well-defined signed ξ: (rows, fit), or None."""
    cor = table["correlation"]
    ok = frictionless[
        (cor["xi"][frictionless] > 0)
        & (cor["xi_error"][frictionless] < 0.2 * cor["xi"][frictionless])
        & res["measurable"][frictionless]
    ]
    if not len(ok):
        return None
    th = cor["theta"]
    return ok, ct.fit_anisotropy(
        np.tile(th, len(ok)),
        np.concatenate([2 * np.pi * cor["xi_theta"][r] / cor["xi"][r] for r in ok]),
        np.concatenate([2 * np.pi * cor["xi_theta_error"][r] / cor["xi"][r] for r in ok]),
        float(np.pi / len(th)),
    )


def anisotropy_abs(table, res, frictionless):
    """Eq. 5.3's shape pooled over ξ_|C|(θ)/mean of the measurable μ = 0 runs: (rows, fit), or None."""
    cor = table["correlation"]
    ok = frictionless[res["measurable"][frictionless]] if "xi_abs_theta" in cor else []
    if not len(ok):
        return None
    th = cor["theta"]
    mean = np.nanmean(cor["xi_abs_theta"][ok], axis=1)
    return ok, ct.fit_anisotropy(
        np.tile(th, len(ok)),
        np.concatenate([cor["xi_abs_theta"][r] / m for r, m in zip(ok, mean)]),
        np.concatenate([cor["xi_abs_theta_error"][r] / m for r, m in zip(ok, mean)]),
        float(np.pi / len(th)),
    )


def anisotropy_lines(table, res, frictionless):
    """Fig 5.6: the pooled fits of eq. 5.3 (each only where it has runs)."""
    cor, thr = table["correlation"], res["threshold"]
    lines = []
    signed = anisotropy_signed(table, res, frictionless)
    if signed is not None:
        ok, fit = signed
        lines += [
            "",
            quote("anisotropy_fit"),
            f"Ours (gf-correlate's ξ(θ), {len(ok)} runs with δξ/ξ < 0.2, pooled fit of eq. 5.3): a0 = "
            f"{ct.fmt_pm(fit['a0'], fit['a0_error'])}, θ0 = {ct.fmt_pm(fit['theta0'], fit['theta0_error'])} "
            f"(χ²/dof = {fit['chi2_dof']:.2g}); per-run a0 from {np.nanmin(cor['a0'][ok]):.2f} to "
            f"{np.nanmax(cor['a0'][ok]):.2f}.",
        ]
    absolute = anisotropy_abs(table, res, frictionless)
    if absolute is not None:
        ok, fit = absolute
        dense = ok[res["ratio"][ok] >= thr]
        lines += [
            "",
            f"Ours, decay length per direction (gf-correlate's ξ_|C|(θ) over its mean, {len(ok)} "
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
    return lines


def cluster_sizes(clusters, i):
    """The contact labels of window i and the sizes of its clusters (label 0: no contact)."""
    labels = clusters["label"][clusters["grain_offset"][i] : clusters["grain_offset"][i + 1]]
    sizes = np.bincount(labels)[1:]
    return labels, sizes[sizes > 0]


def cluster_lines(clusters_path):
    """Fig 5.1: the contact clusters of each window."""
    cl_table = ct.read_table(clusters_path)
    cl, cr = cl_table["clusters"], cl_table["runs"]
    lines = [
        "",
        quote("clusters"),
        *head("run", "window (steps)", "grains in contact", "clusters", "largest", "mean size"),
    ]
    for i in range(len(cr["input"])):
        labels, sizes = cluster_sizes(cl, i)
        lines.append(
            f"| `{os.path.basename(cr['input'][i])}` | "
            f"{int(cl['last_step'][i] - cl['first_step'][i]) + 1} | {int((labels > 0).sum())} | "
            f"{len(sizes)} | {sizes.max() if len(sizes) else 0} | "
            f"{sizes.mean() if len(sizes) else 0:.2f} |"
        )
    return lines


def section(correlate_path, clusters_path):
    """Chapter 5: force correlations, P(f) and ν_bc beside the statements of thesis ch. 5."""
    table = ct.read_table(correlate_path)
    res = ct.analyse(table)
    runs = table["runs"]
    frictionless = ct.select(table, friction=0.0)
    es = np.unique(runs["restitution"][frictionless])
    nus = np.unique(runs["packing_fraction"][frictionless])
    lines = (
        intro(table, res, correlate_path)
        + xi_lines(table, res, es, nus)
        + trend_lines(trends(table, res, es, nus), nus[0], res["threshold"])
        + nu_bc_lines(table, res)
        + anisotropy_lines(table, res, frictionless)
    )
    return lines + (cluster_lines(clusters_path) if clusters_path else [])


def nu_c_interval(fits, i):
    """A fit's ν_c with its interval ([low, high], or [low, ∞) when open above)."""
    hi = fits["nu_c_high"][i]
    return f"{fits['nu_c'][i]:.4f} [{fits['nu_c_low'][i]:.4f}, " + (f"{hi:.4f}]" if math.isfinite(hi) else "∞)")


def jamming_fit(fits, mu, e, quantity, fixed=None):
    """The row of the fit of one quantity at (μ, e), exponent free or fixed (None: no such fit)."""
    pick = (fits["friction"] == mu) & (fits["restitution"] == e) & np.array([x == quantity for x in fits["quantity"]])
    pick &= np.isnan(fits["exponent_fixed"]) if fixed is None else (fits["exponent_fixed"] == fixed)
    return int(np.flatnonzero(pick)[0]) if pick.any() else None


def jamming_section(jamming_path):
    """ν_c(μ, e) from the divergence of the steady stresses (jamming_point.py), beside §5.2."""
    table = outputs.read_table(jamming_path, ("fits", "skipped"))
    fits, skipped, prm = table["fits"], table["skipped"], table["parameters"]
    lines = [
        *subsection("ν_c from the steady stresses (jamming_point.py)", "nu_c_diverges"),
        f"Table `{jamming_path}`: per (μ, e), the runs at ν ≥ {float(prm['from_nu']):g} fitted to "
        "q = A (ν_c − ν)^−β, q = p/(mγ̇²) or s/(mγ̇²) (weighted least squares in ln q; ν_c's interval where "
        "χ² stays within max(1, χ²/dof) of its minimum; `pipelines/analysis/jamming_point.py`). The thesis "
        "estimates ν_c ≈ 0.845 at μ = 0 (Fig. 5.10). An extrapolation: ν_c lies above every run.",
    ]
    keys = sorted({(float(m), float(e)) for m, e in zip(fits["friction"], fits["restitution"])})
    if keys:
        lines += [
            "",
            *head("μ", "e", "runs", "densest ν", "ν_c from p, β free", "β", "χ²/dof", "ν_c from p, β = 2",
                  "ν_c from s, β free", "β"),
        ]
    for mu, e in keys:
        p, sh = jamming_fit(fits, mu, e, "pressure_scaled"), jamming_fit(fits, mu, e, "shear_stress_scaled")
        p2 = jamming_fit(fits, mu, e, "pressure_scaled", 2.0)
        lines.append(
            f"| {mu:g} | {e:g} | {int(fits['points'][p])} | {fits['nu_max'][p]:g} | {nu_c_interval(fits, p)} | "
            f"{fits['exponent'][p]:.2f} | {fits['chi2'][p]:.1f}/{int(fits['dof'][p])} | "
            + (nu_c_interval(fits, p2) if p2 is not None else "—")
            + f" | {nu_c_interval(fits, sh)} | {fits['exponent'][sh]:.2f} |"
        )
    if len(skipped["friction"]):
        lines.append("")
        lines.append(
            f"Not fitted (fewer than {jamming_point.MIN_POINTS} runs at ν ≥ {float(prm['from_nu']):g}): "
            + ", ".join(
                f"μ = {m:g}, e = {e:g} ({int(n)})"
                for m, e, n in zip(skipped["friction"], skipped["restitution"], skipped["points"])
            )
            + "."
        )
    return lines
