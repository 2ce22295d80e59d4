#!/usr/bin/env python3
"""ch6_network.py --figure 6.5|6.6|6.7|6.8 NETWORK.h5 OUTPUT.png [--halfstep HALFSTEP.h5]
[--restitution E --nu NU]: the force-network figures of thesis §6.2 from gf-network's table.

6.5: polar plots of (a) the contact distribution C(θ) and (b) F_bc(θ)/⟨F_bc⟩ of the run nearest
     to (--restitution, --nu) (default e = 0, ν = 0.79, as the thesis), the histograms of
     /histograms extended to [0, 2π) by π-periodicity, with the first-order forms of eqs.
     6.20-6.21 from the run's a_c, a′_c, a_f, a′_f (lines).
6.6: the four Fourier components a_c, a′_c, a_f, a′_f against ν, one series per e, and the
     4θ components of C and F_bc measured from the histograms (the thesis' "next order"
     bound 0.01 dashed).
6.7: (a) the coordination z (long-lived contacts) against ν per e; inset: z at the default step
     (filled) and at half of it (open), the pairs of rows of HALFSTEP.h5 with equal ν, e and dt
     ratio 2; (b) Φ (filled) and Ψ (open) against ν per e, the thesis' Φ ≈ 0.83 dashed.
6.8: (a-c) the left-hand sides of eqs. 6.27-6.29 against their predicted right-hand sides,
     log-log over the decades the data span, the line y = x; colour by e, the main reading
     (sums continued to the non-integer ξ/ξ_el − 1) filled, the floor reading open. Rows with a
     side ≤ 0 cannot be drawn on a log axis: each panel counts them (and rows without a ξ/ξ_el)."""
import argparse
import sys

import numpy as np

from granflow import network_table as nt
from granflow.plotting import plt, save_figure

COMPONENTS = (("a_c", "$a_c$"), ("a_c_prime", "$a'_c$"), ("a_f", "$a_f$"), ("a_f_prime", "$a'_f$"))


def colours(table):
    """A colour per restitution of the table, in the legend's order (e decreasing)."""
    return {e: f"C{k}" for k, e in enumerate(nt.restitutions(table))}


def legend(ax, **kwargs):
    """A legend if the panel has labelled artists (a table whose values are all NaN has none)."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(**kwargs)


def series(ax, table, name, colour, e, marker="o", filled=True, label=None, ms=4):
    """One quantity of /runs against ν at restitution e, with its error bars."""
    rows = nt.select(table, e)
    nu = nt.column(table, "packing_fraction")[rows]
    y, err = nt.column(table, name)[rows], nt.column(table, name + "_error")[rows]
    shown = np.isfinite(y)
    ax.errorbar(
        nu[shown],
        y[shown],
        yerr=np.where(np.isfinite(err[shown]), err[shown], 0),
        fmt=marker + "-",
        color=colour,
        mfc=colour if filled else "none",
        ms=ms,
        lw=0.8,
        elinewidth=0.8,
        capsize=2,
        label=label,
    )


def figure_6_5(table, args):
    row = nt.nearest(table, args.restitution, args.nu)
    h = table["histograms"]
    theta = np.asarray(h["theta"], dtype=float)
    full = np.concatenate([theta, theta + np.pi])
    fine = np.linspace(0, 2 * np.pi, 361)
    get = lambda name: nt.column(table, name)[row]  # noqa: E731
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.2), subplot_kw={"projection": "polar"})
    panels = (
        (
            np.asarray(h["C"], dtype=float)[row],
            (1 + get("a_c") * np.sin(2 * fine) + get("a_c_prime") * np.cos(2 * fine)) / (2 * np.pi),
            "(a) C(θ)",
            f"$a_c$ = {nt.fmt_pm(get('a_c'), get('a_c_error'))}, $a'_c$ = "
            f"{nt.fmt_pm(get('a_c_prime'), get('a_c_prime_error'))}",
        ),
        (
            np.asarray(h["binary_force"], dtype=float)[row],
            1 + get("a_f") * np.sin(2 * fine) + get("a_f_prime") * np.cos(2 * fine),
            r"(b) $F_{bc}(\theta)/\langle F_{bc}\rangle$",
            f"$a_f$ = {nt.fmt_pm(get('a_f'), get('a_f_error'))}, $a'_f$ = "
            f"{nt.fmt_pm(get('a_f_prime'), get('a_f_prime_error'))}",
        ),
    )
    for ax, (data, fit, title, text) in zip(axes, panels):
        # A θ bin without contacts has no mean force (NaN): it is left out, as is a fit whose
        # components were not measured.
        data = np.concatenate([data, data])
        shown = np.isfinite(data)
        ax.plot(full[shown], data[shown], "o", ms=3, color="C0", label="measured (histogram)")
        if np.isfinite(fit).all():
            ax.plot(fine, fit, "-", color="C3", lw=1.2, label="first order, eqs. 6.20–6.21")
        ax.set_title(title + "\n" + text, fontsize=9)
        top = np.concatenate([data[shown], fit[np.isfinite(fit)]])
        ax.set_ylim(0, 1.15 * top.max() if len(top) and top.max() > 0 else 1)
        ax.tick_params(labelsize=7)
    legend(axes[1], fontsize=7, loc="lower left", bbox_to_anchor=(0.7, -0.12))
    nu, e = nt.column(table, "packing_fraction")[row], nt.column(table, "restitution")[row]
    fig.suptitle(
        f"Thesis Fig. 6.5: e = {e:g}, ν = {nu:.3f} (the run nearest to e = {args.restitution:g}, ν = {args.nu:g});\n"
        f"θ from the flow direction x, histograms folded into [0, π) and repeated",
        fontsize=9,
        y=1.06,
    )
    return fig


def figure_6_6(table, args):
    fig, axes = plt.subplots(2, 3, figsize=(14, 8))
    fig.subplots_adjust(wspace=0.3)
    colour = colours(table)
    for ax, (name, label) in zip((axes[0, 0], axes[0, 1], axes[1, 0], axes[1, 1]), COMPONENTS):
        for e, c in colour.items():
            series(ax, table, name, c, e, label=f"e = {e:g}")
        ax.axhline(0, color="k", lw=0.5)
        ax.set_xlabel("packing fraction ν")
        ax.set_ylabel(label)
    legend(axes[0, 0], fontsize=7)
    for ax, (names, what) in zip(
        axes[:, 2], ((("a4_c", "a4_c_prime"), "C(θ)"), (("a4_f", "a4_f_prime"), r"$F_{bc}(\theta)$"))
    ):
        for e, c in colour.items():
            rows = nt.select(table, e)
            nu = nt.column(table, "packing_fraction")[rows]
            for name, marker in zip(names, ("o", "s")):
                y, err = np.abs(nt.column(table, name)[rows]), nt.column(table, name + "_error")[rows]
                shown = np.isfinite(y)
                ax.errorbar(
                    nu[shown],
                    y[shown],
                    yerr=np.where(np.isfinite(err[shown]), err[shown], 0),
                    fmt=marker,
                    color=c,
                    mfc="none" if marker == "s" else c,
                    ms=4,
                    elinewidth=0.8,
                    capsize=2,
                )
        ax.axhline(nt.THESIS_NEXT_ORDER, color="k", ls="--", lw=0.8)
        ax.set_xlabel("packing fraction ν")
        ax.set_ylabel(f"|4θ components| of {what}")
        ax.set_title(
            f"next order of {what}: ● sin 4θ, □ cos 4θ; dashed: thesis' bound {nt.THESIS_NEXT_ORDER:g}", fontsize=8
        )
    fig.suptitle(
        "Thesis Fig. 6.6: the Fourier components of eqs. 6.20–6.21 (fabric and force-fabric tensors) "
        "and the measured next order",
        fontsize=10,
    )
    return fig


def figure_6_7(table, args):
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 5))
    colour = colours(table)
    for e, c in colour.items():
        series(left, table, "coordination", c, e, label=f"e = {e:g}")
        series(right, table, "Phi", c, e, label=f"Φ, e = {e:g}")
        series(right, table, "Psi", c, e, marker="s", filled=False, label=f"Ψ, e = {e:g}")
    right.axhline(nt.THESIS_PHI, color="k", ls="--", lw=0.8, label=f"thesis: Φ ≈ {nt.THESIS_PHI:g}")
    left.set_ylabel("z (long-lived contacts, all grains)")
    right.set_ylabel("Φ, Ψ (eq. 6.23, twice the means)")
    for ax, title in ((left, "(a)"), (right, "(b)")):
        ax.set_xlabel("packing fraction ν")
        ax.set_title(title, loc="left")
    legend(left, fontsize=7, loc="lower right")
    legend(right, fontsize=7, loc="lower left")
    # z grows with ν: the upper left of panel (a) is where the inset hides the fewest points.
    inset = left.inset_axes([0.09, 0.58, 0.38, 0.34])
    pairs = []
    if args.halfstep:
        half = nt.read_table(args.halfstep)
        pairs = nt.step_pairs(half)
    if pairs:
        nu, z = nt.column(half, "packing_fraction"), nt.column(half, "coordination")
        dz = nt.column(half, "coordination_error")
        hcolour = {**{e: f"C{len(colour) + k}" for k, e in enumerate(nt.restitutions(half))}, **colour}
        for i, j in pairs:
            c = hcolour[float(nt.column(half, "restitution")[i])]
            inset.errorbar(nu[i], z[i], yerr=dz[i] if np.isfinite(dz[i]) else 0, fmt="o", color=c, ms=4, capsize=2)
            inset.errorbar(
                nu[j], z[j], yerr=dz[j] if np.isfinite(dz[j]) else 0, fmt="s", color=c, mfc="none", ms=6, capsize=2
            )
        inset.set_title("z: ● default step, □ half of it", fontsize=7)
    else:
        inset.text(0.5, 0.5, "no half-step pairs", ha="center", va="center", fontsize=7, transform=inset.transAxes)
    inset.tick_params(labelsize=6)
    inset.set_xlabel("ν", fontsize=7)
    fig.suptitle(
        "Thesis Fig. 6.7: coordination z and the network geometry Φ, Ψ (long-lived contacts: in contact "
        "with an impulse in this step and the previous one)",
        fontsize=9,
    )
    return fig


def figure_6_8(table, args):
    fig, axes = plt.subplots(1, 3, figsize=(16, 5.4))
    colour = colours(table)
    e_all = nt.column(table, "restitution")
    for letter, ax, (equation, number, lhs_name) in zip("abc", axes, nt.EQUATIONS):
        shown = []
        counts = []
        for reading, filled in (("", True), ("_floor", False)):
            lhs, lhs_err, rhs, rhs_err = nt.lhs_rhs(table, equation, reading)
            stats = nt.collapse(lhs, rhs)
            counts.append((reading or "main", stats))
            ok = np.isfinite(lhs) & np.isfinite(rhs)
            with np.errstate(invalid="ignore"):
                ok &= (lhs > 0) & (rhs > 0)
            for e, c in colour.items():
                sel = ok & (np.abs(e_all - e) <= 1e-6)
                if not sel.any():
                    continue
                xerr = np.where(np.isfinite(rhs_err[sel]), np.minimum(rhs_err[sel], 0.999 * rhs[sel]), 0)
                yerr = np.where(np.isfinite(lhs_err[sel]), np.minimum(lhs_err[sel], 0.999 * lhs[sel]), 0)
                ax.errorbar(
                    rhs[sel],
                    lhs[sel],
                    xerr=xerr,
                    yerr=yerr,
                    fmt="o",
                    color=c,
                    mfc=c if filled else "none",
                    ms=5,
                    elinewidth=0.6,
                    capsize=1.5,
                    label=f"e = {e:g}" if filled else None,
                )
            shown += list(lhs[ok]) + list(rhs[ok])
        if shown:
            lo, hi = min(shown) / 2, max(shown) * 2
            ax.plot([lo, hi], [lo, hi], "k-", lw=0.8, label="y = x")
            ax.set_xlim(lo, hi)
            ax.set_ylim(lo, hi)
        else:
            ax.text(0.5, 0.5, "no row with lhs > 0 and rhs > 0", ha="center", va="center", transform=ax.transAxes)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(f"rhs of eq. {number} (predicted)")
        ax.set_ylabel(f"lhs {lhs_name} (measured)")
        note = "\n".join(
            f"{name.lstrip('_')}: {s['used']} drawn, {s['non_positive']} with a side ≤ 0, {s['missing']} without a value"
            for name, s in counts
        )
        ax.set_title(f"({letter}) eq. {number}\n{note}", fontsize=7)
        legend(ax, fontsize=7, loc="upper left")
    fig.suptitle(
        "Thesis Fig. 6.8: measured left-hand sides against the force-network prediction (no fit); "
        "filled: sums continued to ξ/ξ_el − 1, open: sums up to ⌊ξ/ξ_el − 1⌋",
        fontsize=9,
    )
    return fig


FIGURES = {"6.5": figure_6_5, "6.6": figure_6_6, "6.7": figure_6_7, "6.8": figure_6_8}


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--figure", required=True, choices=sorted(FIGURES))
    ap.add_argument("--halfstep", help="gf-network table of the half-step runs and their default-step pairs (6.7)")
    ap.add_argument("--restitution", type=float, default=0.0, help="e of Fig. 6.5's run (nearest)")
    ap.add_argument("--nu", type=float, default=0.79, help="ν of Fig. 6.5's run (nearest)")
    ap.add_argument("network")
    ap.add_argument("output")
    args = ap.parse_args()
    table = nt.read_table(args.network)
    if nt.rows(table) == 0:
        sys.exit(f"ch6_network.py: {args.network} has no runs")
    fig = FIGURES[args.figure](table, args)
    save_figure(fig, args.output)


if __name__ == "__main__":
    main()
