#!/usr/bin/env python3
"""phase_step.py --default-step H --output OUT.h5 [--markdown OUT.md] [--figure OUT.png] TABLE.h5...:
the binary-collision crossover ν_bc(e) of Figs 5.9-5.10 and the dense/dilute class of every run
against the strain step h = γ̇dt.

Each TABLE is a chapter-5 gf-correlate sweep (ch5_correlate.h5, with --reference) whose runs share
one step, read from the runs' own /parameters (|rate|·dt); tables at one step are refused. ν_bc is
gf-correlate's (/sweep/nu_bc_abs: where ξ_|C|/ξ_el first crosses the threshold upward in ν), per
(e, μ); its series over h is classed by convergence.py's rule (converged, converging with a limit,
regularisation-dependent, unsettled). A run is dense when its ξ_|C|/ξ_el is at or above the
threshold; a flip is a (ν, e, μ) whose class at the finest step differs from the default step's.

Output (HDF5, written atomically, with the provenance of every analysis table): /parameters
(program, script_sha256, command_line, default_step, threshold); /runs/input, input_sha256 (the
tables); /crossover/<column> [rows], one per (step, e, μ): step, restitution, friction, nu_bc,
nu_bc_error, status (bracketed, all_below, all_above, ...), nu_below, nu_above (the runs either side of a bracketed
crossing), nu_low, nu_high (the ν range of the measurable runs of the series); /classes/<column>
[rows], one per (e, μ) with a bracketed ν_bc at two steps or more: restitution, friction, class and
the numbers of convergence.classify; /runs_by_step/<column> [rows], one per (step, run): step,
packing_fraction, restitution, friction, ratio, ratio_error, measurable, dense.
"""
import argparse
import math
import shlex
import sys

import numpy as np

from analysis import convergence
from granflow import correlation_table as ct
from granflow import outputs
from granflow.hdf5 import sha256

CLASS_COLUMNS = (
    "steps",
    "span",
    "default_value",
    "default_error",
    "finest_step",
    "finest_value",
    "finest_error",
    "limit",
    "limit_error",
    "limit_exponent",
    "step_1pct",
    "exponent",
    "exponent_error",
)
NU_C = 0.845  # the thesis' jamming packing fraction, as in Fig. 5.10


def table_step(table, cache):
    """The one strain step of a table's runs (ValueError when they differ or cannot be read)."""
    steps = set()
    for path in table["runs"]["input"]:
        path = path.decode() if isinstance(path, bytes) else str(path)
        try:
            steps.add(convergence.run_key(path, cache)[5])
        except (OSError, KeyError) as error:
            raise ValueError(f"{table['path']}: cannot read the step of its run {path}: {error}")
    if len(steps) != 1:
        raise ValueError(f"{table['path']}: its runs have {len(steps)} strain steps ({sorted(steps)}); one is needed")
    return steps.pop()


def read_steps(paths):
    """{step: (table, analyse(table))}, one table per step."""
    cache, by_step = {}, {}
    for path in paths:
        table = ct.read_table(path)
        if "sweep" not in table:
            raise ValueError(f"{path}: no /sweep: made without --reference; ν_bc needs the reference run")
        h = table_step(table, cache)
        if h in by_step:
            raise ValueError(f"{path}: a second table at step {h:g} (the first: {by_step[h][0]['path']})")
        by_step[h] = (table, ct.analyse(table))
    if len(by_step) < 2:
        raise ValueError("need tables at two strain steps or more")
    return by_step


def crossover_rows(by_step):
    """One row per (step, e, μ): gf-correlate's crossing, and the ν range of the measurable runs
    it was sought over (nu_low, nu_high: a crossing not bracketed lies beyond one of them)."""
    rows = []
    for h in sorted(by_step, reverse=True):
        table, res = by_step[h]
        for s in res["series"]:
            rows_of = [k for k in ct.select(table, restitution=s["restitution"], friction=s["friction"])
                       if res["measurable"][k]]
            nu = table["runs"]["packing_fraction"][rows_of] if rows_of else np.array([math.nan])
            rows.append({"step": h, **{k: s[k] for k in ("restitution", "friction", "nu_bc", "nu_bc_error",
                                                            "status", "nu_below", "nu_above")},
                         "nu_low": float(np.min(nu)), "nu_high": float(np.max(nu))})
    return rows


def run_rows(by_step):
    rows = []
    for h in sorted(by_step, reverse=True):
        table, res = by_step[h]
        runs = table["runs"]
        reference = set(res["reference_rows"])
        for k in range(len(runs["packing_fraction"])):
            if k in reference:
                continue
            ratio = float(res["ratio"][k])
            measurable = bool(res["measurable"][k])
            rows.append(
                {
                    "step": h,
                    "packing_fraction": round(float(runs["packing_fraction"][k]), 6),
                    "restitution": round(float(runs["restitution"][k]), 6),
                    "friction": round(float(runs["friction"][k]), 6),
                    "ratio": ratio,
                    "ratio_error": float(res["ratio_error"][k]),
                    "measurable": measurable,
                    "dense": measurable and np.isfinite(ratio) and ratio >= res["threshold"],
                }
            )
    return rows


def classes(crossovers, default_step):
    """convergence.classify on ν_bc(h) per (e, μ), over its bracketed steps."""
    out = []
    for key in sorted({(r["restitution"], r["friction"]) for r in crossovers}):
        series = [r for r in crossovers if (r["restitution"], r["friction"]) == key and r["status"] == "bracketed"]
        if len(series) < 2:
            continue
        c = convergence.classify(
            [r["step"] for r in series], [r["nu_bc"] for r in series], [r["nu_bc_error"] for r in series], default_step
        )
        out.append({"restitution": key[0], "friction": key[1], **c})
    return out


def flips(runs, default_step):
    """Runs measurable at the default and the finest step whose dense/dilute class differs."""
    finest = min(r["step"] for r in runs)
    at = lambda h: {  # noqa: E731
        (r["packing_fraction"], r["restitution"], r["friction"]): r
        for r in runs
        if math.isclose(r["step"], h, rel_tol=1e-9) and r["measurable"] and np.isfinite(r["ratio"])
    }
    coarse, fine = at(default_step), at(finest)
    common = sorted(set(coarse) & set(fine))
    changed = [k for k in common if coarse[k]["dense"] != fine[k]["dense"]]
    return finest, common, changed


def crossing_text(r):
    if r["status"] == "bracketed":
        return ct.fmt_pm(r["nu_bc"], r["nu_bc_error"])
    if r["status"] == "all_below":
        return f"> {r['nu_high']:.3f}"
    if r["status"] == "all_above":
        return f"< {r['nu_low']:.3f}"
    return r["status"].replace("_", " ")


def markdown(by_step, crossovers, cls, runs, default_step, threshold):
    steps = sorted(by_step, reverse=True)
    keys = sorted({(r["restitution"], r["friction"]) for r in crossovers})
    lines = [f"ν_bc(e) (ξ_|C|/ξ_el = {threshold:g}) against the strain step γ̇dt (default {default_step:g})", ""]
    lines.append("| e | μ | " + " | ".join(f"γ̇dt = {h:g}" for h in steps) + " | class |")
    lines.append("|---|---|" + "---|" * len(steps) + "---|")
    for key in keys:
        cells = []
        for h in steps:
            match = [r for r in crossovers if r["step"] == h and (r["restitution"], r["friction"]) == key]
            cells.append(crossing_text(match[0]) if match else "–")
        c = [x for x in cls if (x["restitution"], x["friction"]) == key]
        cells.append(convergence.class_text(c[0]) if c else "fewer than two bracketed steps")
        lines.append(f"| {key[0]:g} | {key[1]:g} | " + " | ".join(cells) + " |")
    lines += ["", "ξ_el (reference run, σ) per step: " + ", ".join(
        f"{h:g}: {ct.fmt_pm(by_step[h][1]['xi_el'] / ct.mean_diameter(by_step[h][0]), by_step[h][1]['xi_el_error'] / ct.mean_diameter(by_step[h][0]))}"
        for h in steps)]
    finest, common, changed = flips(runs, default_step)
    dense = {h: sum(1 for r in runs if r["step"] == h and r["dense"]) for h in steps}
    measured = {h: sum(1 for r in runs if r["step"] == h and r["measurable"]) for h in steps}
    lines += ["", "Dense runs (ξ_|C|/ξ_el ≥ threshold) of the measurable ones per step: " + ", ".join(
        f"{h:g}: {dense[h]} of {measured[h]}" for h in steps)]
    lines += ["", f"Runs whose class differs between γ̇dt = {default_step:g} and {finest:g}: {len(changed)} of {len(common)}"
              + (": " + ", ".join(f"(ν {k[0]:.3f}, e {k[1]:g}, μ {k[2]:g})" for k in changed) if changed else "")]
    return "\n".join(lines) + "\n"


def figure(path, by_step, crossovers, default_step, threshold):
    from granflow.plotting import plt, save_figure

    steps = sorted(by_step, reverse=True)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.6))
    for i, h in enumerate(steps):
        series = sorted(
            (r for r in crossovers if r["step"] == h and r["status"] == "bracketed" and r["friction"] == 0),
            key=lambda r: r["restitution"],
        )
        label = f"γ̇dt = {h:g}" + (" (default)" if math.isclose(h, default_step, rel_tol=1e-9) else "")
        if series:
            left.errorbar([r["nu_bc"] for r in series], [r["restitution"] for r in series],
                          xerr=[r["nu_bc_error"] for r in series], fmt="o-", ms=4, capsize=2, color=f"C{i}", label=label)
        for r in crossovers:
            if r["step"] == h and r["friction"] == 0 and r["status"] in ("all_below", "all_above"):
                beyond = r["status"] == "all_below"
                left.plot(r["nu_high"] if beyond else r["nu_low"], r["restitution"], ">" if beyond else "<",
                          ms=7, mfc="none", color=f"C{i}")
        table, res = by_step[h]
        reference = set(res["reference_rows"])
        rows = [k for k in ct.select(table, restitution=0.5, friction=0.0) if res["measurable"][k] and k not in reference]
        if rows:
            right.errorbar(table["runs"]["packing_fraction"][rows], res["ratio"][rows], yerr=res["ratio_error"][rows],
                           fmt="o-", ms=3, capsize=2, color=f"C{i}", label=label)
    left.axvline(NU_C, color="k", ls="--", lw=1, label="ν_c ≈ 0.845 (thesis)")
    left.set_xlabel("packing fraction ν_bc")
    left.set_ylabel("restitution e")
    left.set_title("ν_bc(e), μ = 0, at each strain step (hollow arrows: beyond the runs' ν range)", fontsize=9)
    left.legend(fontsize=7)
    right.axhline(threshold, color="k", ls=":", lw=1, label=f"threshold {threshold:g}")
    right.set_xlabel("packing fraction ν")
    right.set_ylabel("ξ_|C| / ξ_el")
    right.set_title("ξ_|C|/ξ_el at e = 0.5, μ = 0", fontsize=9)
    right.legend(fontsize=7)
    fig.suptitle("Fig. 5.10's crossover against the strain step γ̇dt", fontsize=10)
    save_figure(fig, path)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--default-step", type=float, required=True, help="the step of the reproduction's figures")
    ap.add_argument("-o", "--output", required=True, help="HDF5 table to write")
    ap.add_argument("--markdown", help="also write the tables as Markdown here")
    ap.add_argument("--figure", help="also draw ν_bc(e) and ξ_|C|/ξ_el at each step here (PNG)")
    ap.add_argument("tables", nargs="+", help="chapter-5 gf-correlate tables, one per strain step")
    args = ap.parse_args(argv)
    if not (math.isfinite(args.default_step) and args.default_step > 0):
        ap.error(f"--default-step: must be a positive number (got {args.default_step})")
    try:
        by_step = read_steps(args.tables)
        if not any(math.isclose(h, args.default_step, rel_tol=1e-9) for h in by_step):
            raise ValueError(f"--default-step {args.default_step:g}: no table at it (steps {sorted(by_step)})")
        thresholds = {by_step[h][1]["threshold"] for h in by_step}
        if len(thresholds) != 1:
            raise ValueError(f"the tables use different thresholds {sorted(thresholds)}")
    except (OSError, KeyError, ValueError) as error:
        print(f"phase_step.py: {error}", file=sys.stderr)
        return 2
    threshold = thresholds.pop()
    crossovers = crossover_rows(by_step)
    runs = run_rows(by_step)
    cls = classes(crossovers, args.default_step)
    with outputs.table(
        args.output,
        __file__,
        shlex.join(sys.argv),
        {"default_step": args.default_step, "threshold": threshold},
        [(path, sha256(path)) for path in args.tables],
    ) as f:
        # Every column is a number (γ̇dt, ν, e, μ, ratios, counts).
        for name, rows in (("crossover", crossovers), ("runs_by_step", runs)):
            outputs.column_group(f, name, {column: [r[column] for r in rows] for column in (rows[0] if rows else ())},
                                 "1")
        columns = ("restitution", "friction", "class") + CLASS_COLUMNS
        outputs.column_group(f, "classes", {column: [c[column] for c in cls] for column in columns} if cls else {},
                             "1")
    if args.markdown:
        outputs.write_text(args.markdown, markdown(by_step, crossovers, cls, runs, args.default_step, threshold))
    if args.figure:
        figure(args.figure, by_step, crossovers, args.default_step, threshold)
    return 0


if __name__ == "__main__":
    sys.exit(main())
