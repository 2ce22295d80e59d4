#!/usr/bin/env python3
"""Render the measured tables of docs/performance.md and docs/method/friction_solver.md
from the data files under bench/results/<machine>/.

Usage:
  render_performance.py --check [--root REPO] [--machine NAME]   exit 1, naming each table,
      when a page's table differs from its rendering, when a table's data file is missing,
      or when a page lacks the markers of a table (or has markers of an unknown one)
  render_performance.py --write [--root REPO] [--machine NAME]   rewrite the tables in place
  render_performance.py --show TABLE                             print one rendered table

A page holds each table between marker comments:

  <!-- table: engine_steady -->
  | ... rendered markdown ... |
  <!-- end table -->

Every data file is CSV with the columns
  commit, date, <key columns>, quantity, value, unit, command, note
one row per measured figure: `commit` is the build it was measured on, `date` the day when
the page gave one, `value` the figure as measured (a text: ranges such as 2254–2300 stay
ranges), `command` what re-measures it. A table row is one combination of its key columns, in
the order the file first names it; a cell is the value of the LAST row of the file with that
key and quantity, so a new measurement is appended below the old one, which stays as history.

Python 3 standard library only; run by ctest as `docs.PerformanceTables`.
"""
import argparse
import csv
import os
import sys
import tempfile

MACHINE = "epyc-2core"
PAGES = ["docs/performance.md", "docs/method/friction_solver.md"]
FIXED = ["commit", "date", "quantity", "value", "unit", "command", "note"]

SUPERSCRIPT = str.maketrans("0123456789", "⁰¹²³⁴⁵⁶⁷⁸⁹")


def power_of_ten(text):
    """'1000' -> '10³'; anything that is not a power of ten (from 10) stays as it is."""
    if text.isdigit() and len(text) > 1 and text[0] == "1" and set(text[1:]) == {"0"}:
        return "10" + str(len(text) - 1).translate(SUPERSCRIPT)
    return text


# Each table: its data file, its key columns, and its columns as (header, source), where the
# source is a key column ("key:NAME", optionally "key:NAME:pow10"), a quantity ("q:NAME"), or
# the command of the row's last quantity ("command"). merge=True joins rows whose other cells
# are all equal into one.
def K(name, pow10=False):
    return "key:" + name + (":pow10" if pow10 else "")


def Q(name):
    return "q:" + name


TABLES = {
    # --- docs/performance.md ---
    "pipeline": dict(
        file="pipeline.csv", keys=["what"],
        columns=[("what", K("what")), ("wall time", Q("wall_time")), ("CPU", Q("cpu_time")),
                 ("other", Q("other")), ("command", "command")]),
    "packing": dict(
        file="packing.csv", keys=["N"],
        columns=[("N", K("N", True)), ("wall time, s", Q("wall_time")), ("FIRE steps", Q("fire_steps")),
                 ("max overlap / σ", Q("max_overlap")), ("ns per grain and step", Q("ns_per_grain_step"))]),
    "engine_steady": dict(
        file="engine_steady.csv", keys=["N"],
        columns=[("N", K("N", True)), ("steps/s", Q("steps_per_s")), ("updates/s", Q("updates_per_s")),
                 ("ns per grain-step", Q("ns_per_grain_step")), ("sweeps per step", Q("sweeps_per_step")),
                 ("engine memory, B per grain", Q("bytes_per_grain"))]),
    "engine_paths": dict(
        file="engine_paths.csv", keys=["case", "N"],
        columns=[("case", K("case")), ("N", K("N", True)), ("steps/s", Q("steps_per_s")),
                 ("s per strain", Q("s_per_strain")), ("sweeps/step", Q("sweeps_per_step")),
                 ("updates/s", Q("updates_per_s")), ("ns per grain-step", Q("ns_per_grain_step")),
                 ("B/grain", Q("bytes_per_grain")), ("steps at the sweep cap", Q("steps_at_cap")),
                 ("filter", Q("filter"))]),
    "engine_threads": dict(
        file="engine_threads.csv", keys=["case"],
        columns=[("case", K("case")), ("measured", Q("value")), ("command", "command")]),
    "friction_cost": dict(
        file="friction_solvers.csv", keys=["N", "nu"],
        columns=[("N", K("N", True)), ("ν", K("nu")), ("timed steps", Q("timed_steps")),
                 ("contacts", Q("contacts")),
                 ("GS alone: sweeps/step", Q("gs_sweeps_per_step")), ("at the cap", Q("gs_steps_at_cap")),
                 ("s/strain", Q("gs_s_per_strain")),
                 ("default: sweeps/step", Q("default_sweeps_per_step")),
                 ("cluster solves/step", Q("default_cluster_solves_per_step")),
                 ("largest cluster, rows", Q("default_largest_cluster")),
                 ("at the cap", Q("default_steps_at_cap")), ("s/strain", Q("default_s_per_strain")),
                 ("gain", Q("gain"))]),
    "friction_against": dict(
        file="friction_against.csv", keys=["N", "nu"],
        columns=[("N", K("N", True)), ("ν", K("nu")),
                 ("issue-24 build: sweeps/step", Q("old_sweeps_per_step")), ("s/strain", Q("old_s_per_strain")),
                 ("today: sweeps/step", Q("new_sweeps_per_step")), ("s/strain", Q("new_s_per_strain")),
                 ("gain", Q("gain"))]),
    "friction_peer": dict(
        file="peer_friction.csv", keys=["program"],
        columns=[("program", K("program")), ("CPU s, 10 strain units", Q("cpu_s")),
                 ("p/γ̇²", Q("p")), ("s/p", Q("s_over_p")), ("T/γ̇²", Q("T"))]),
    "incline": dict(
        file="incline.csv", keys=["mobile_grains"],
        columns=[("mobile grains", K("mobile_grains", True)), ("base", Q("base")), ("steps/s", Q("steps_per_s")),
                 ("sweeps/step", Q("sweeps_per_step")), ("per grain-step", Q("per_grain_step")),
                 ("profile sample per step", Q("profile_sample"))]),
    "correlation": dict(
        file="correlation.csv", keys=["N", "lmax"],
        columns=[("N", K("N", True)), ("ℓ_max", K("lmax")), ("exact pairs", Q("exact")),
                 ("FFT, cells σ/20", Q("fft_20")), ("σ/10", Q("fft_10")), ("σ/5", Q("fft_5")),
                 ("benchmarks", Q("benchmarks"))]),
    "kinetic": dict(
        file="kinetic.csv", keys=["what"],
        columns=[("what", K("what")), ("measured", Q("value")), ("command", "command")]),
    "network": dict(
        file="network.csv", keys=["N"],
        columns=[("N", K("N")), ("contacts", Q("contacts")), ("one frame", Q("frame_time")),
                 ("per contact", Q("per_contact"))]),
    "d2min": dict(
        file="d2min.csv", keys=["N"],
        columns=[("N", K("N")), ("whole (search + fit)", Q("whole")), ("per grain", Q("per_grain")),
                 ("fit on bonds found once", Q("fit_only")), ("unwrapping two stored frames", Q("unwrap"))]),
    "peer_fidelity": dict(
        file="peer.csv", keys=["program"],
        columns=[("program, setting", K("program")), ("ν = 0.6, 10 strain units, N = 2000", Q("cpu_s_nu060")),
                 ("ν = 0.8, 10 strain units, N = 2000", Q("cpu_s_nu080")),
                 ("ν = 0.8, 20 strain units, N = 1000, equal fidelity", Q("cpu_s_equal_fidelity"))]),
    "million": dict(
        file="million.csv", keys=["program"],
        columns=[("program", K("program")), ("N = 10⁵", Q("n1e5")), ("N = 10⁶", Q("n1e6")),
                 ("command (N = 10⁶)", "command")]),
    "million_start": dict(
        file="million_start.csv", keys=["what"],
        columns=[("", K("what")), ("N = 10⁵ (step 1)", Q("n1e5")), ("N = 10⁶ (steps 1 and 2)", Q("n1e6"))]),
    "million_target": dict(
        file="million_target.csv", keys=["case"],
        columns=[("10⁶ grains, idle machine", K("case")), ("µs per grain-step", Q("us_per_grain_step")),
                 ("stepping, s for 50 steps", Q("stepping_s"))]),
    "paper_figures": dict(
        file="paper_cost_figures.csv", keys=["figure"], merge=True,
        columns=[("figure", K("figure")), ("needs", Q("needs")), ("grain-steps", Q("grain_steps")),
                 ("simulations, CPU h", Q("simulations_cpu_h")), ("analyses, CPU h", Q("analyses_cpu_h"))]),
    "paper_kinds": dict(
        file="paper_cost_kinds.csv", keys=["kind"],
        columns=[("simulations of the total, by kind", K("kind")), ("runs", Q("runs")),
                 ("grain-steps", Q("grain_steps")), ("CPU h", Q("cpu_h"))]),
    "paper_grain_step": dict(
        file="paper_cost_grain_step.csv", keys=["nu"],
        columns=[("ν", K("nu")), ("e = 0", Q("e0")), ("W, M at e = 0", Q("warmup_timed_e0")),
                 ("e = 0.5", Q("e05")), ("e = 0.92", Q("e092")), ("elastic gas (equilibrium)", Q("equilibrium"))]),
    # --- docs/method/friction_solver.md ---
    "friction_summary": dict(
        file="friction_solvers.csv", keys=["N", "nu"],
        columns=[("N", K("N", True)), ("ν", K("nu")), ("s/strain, default", Q("default_s_per_strain")),
                 ("s/strain, Gauss–Seidel alone", Q("gs_s_per_strain")), ("gain", Q("gain")),
                 ("sweeps/step, default", Q("default_sweeps_per_step")),
                 ("cluster passes/step", Q("default_cluster_solves_per_step")),
                 ("steps at the 10⁴ cap, default", Q("default_steps_at_cap"))]),
    "friction_profile": dict(
        file="friction_profile.csv", keys=["part"],
        columns=[("part of the time", K("part")), ("N = 10³, ν = 0.78", Q("n1e3_nu078")),
                 ("N = 10⁴, ν = 0.78", Q("n1e4_nu078"))]),
    "friction_quick_runs": dict(
        file="friction_quick_runs.csv", keys=["run"],
        columns=[("quick μ = 0.4 run", K("run")), ("steps at the cap", Q("steps_at_cap")),
                 ("sweeps/step", Q("sweeps_per_step")), ("region solves", Q("region_solves")),
                 ("flow rate, 2nd − 1st half of 200–400 τ", Q("flow_rate_halves"))]),
    "friction_physics": dict(
        file="friction_physics.csv", keys=["nu", "e", "seed_strain"],
        columns=[("ν", K("nu")), ("e", K("e")), ("packing seed, strain", K("seed_strain")),
                 ("CPU s, default / GS alone", Q("cpu_s")), ("Δ(p/γ̇²)/σ", Q("dp")),
                 ("Δ(s/p)/σ", Q("dsp")), ("Δ(T/γ̇²)/σ", Q("dT"))]),
}


def read_rows(path):
    with open(path, newline="", encoding="utf-8") as f:
        reader = csv.DictReader(f)
        missing = [c for c in FIXED if c not in (reader.fieldnames or [])]
        if missing:
            raise ValueError(f"{path}: no column(s) {', '.join(missing)}")
        return list(reader)


def render(name, results):
    """The markdown of table `name` from the files in `results` (raises OSError/ValueError)."""
    spec = TABLES[name]
    path = os.path.join(results, spec["file"])
    if not os.path.isfile(path):
        raise OSError(f"its data file {os.path.relpath(path)} is missing")
    rows = read_rows(path)
    for key in spec["keys"]:
        if rows and key not in rows[0]:
            raise ValueError(f"{spec['file']}: no key column '{key}'")
    order, cells, commands = [], {}, {}
    for row in rows:
        k = tuple(row[key] for key in spec["keys"])
        if k not in cells:
            order.append(k)
            cells[k] = {}
        cells[k][row["quantity"]] = row["value"]  # the last row of a key and quantity wins
        commands[k] = row["command"]
    needed = {src[2:] for _, src in spec["columns"] if src.startswith("q:")}
    known = {row["quantity"] for row in rows}
    if not needed & known:
        raise ValueError(f"{spec['file']}: none of the quantities {sorted(needed)}")
    lines = ["| " + " | ".join(h for h, _ in spec["columns"]) + " |",
             "|" + "---|" * len(spec["columns"])]
    body = []
    for k in order:
        out = []
        for _, src in spec["columns"]:
            if src == "command":
                out.append(f"`{commands[k]}`" if commands[k] else "")
            elif src.startswith("key:"):
                parts = src.split(":")
                value = k[spec["keys"].index(parts[1])]
                out.append(power_of_ten(value) if len(parts) > 2 else value)
            else:
                out.append(cells[k].get(src[2:], ""))
        body.append(out)
    if spec.get("merge"):
        # rows whose other cells are all equal become one row, their first cells joined
        merged = []
        for out in body:
            for m in merged:
                if m[1:] == out[1:]:
                    m[0] += ", " + out[0]
                    break
            else:
                merged.append(list(out))
        body = merged
    for out in body:
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in out) + " |")
    return "\n".join(lines)


def split_page(text):
    """[(kind, name, body)] pieces of a page: ('text', None, s) or ('table', name, s)."""
    pieces, rest = [], text
    while True:
        start = rest.find("<!-- table: ")
        if start < 0:
            pieces.append(("text", None, rest))
            return pieces
        head_end = rest.index("-->", start) + 3
        name = rest[start + len("<!-- table: "):head_end - 3].strip()
        end = rest.find("<!-- end table -->", head_end)
        if end < 0:
            raise ValueError(f"table {name}: no '<!-- end table -->'")
        pieces.append(("text", None, rest[:head_end]))
        pieces.append(("table", name, rest[head_end:end]))
        rest = rest[end:]


def process(root, results, write):
    """Problems found (and, with write, the pages rewritten)."""
    problems, seen = [], set()
    for rel in PAGES:
        path = os.path.join(root, rel)
        if not os.path.isfile(path):
            problems.append(f"{rel}: missing")
            continue
        with open(path, encoding="utf-8") as f:
            text = f.read()
        try:
            pieces = split_page(text)
        except ValueError as e:
            problems.append(f"{rel}: {e}")
            continue
        out = []
        for kind, name, body in pieces:
            if kind == "text":
                out.append(body)
                continue
            seen.add(name)
            if name not in TABLES:
                problems.append(f"{rel}: table {name}: unknown to bench/render_performance.py")
                out.append(body)
                continue
            try:
                rendered = "\n" + render(name, results) + "\n"
            except (OSError, ValueError, KeyError) as e:
                problems.append(f"{rel}: table {name}: {e}")
                out.append(body)
                continue
            if rendered != body and not write:
                problems.append(f"{rel}: table {name}: differs from its rendering from "
                                f"{os.path.relpath(os.path.join(results, TABLES[name]['file']), root)} "
                                f"(bench/render_performance.py --write)")
            out.append(rendered)
        new = "".join(out)
        if write and new != text:
            with open(path, "w", encoding="utf-8") as f:
                f.write(new)
    for name in sorted(set(TABLES) - seen):
        problems.append(f"table {name}: on no page (markers '<!-- table: {name} -->' missing)")
    return problems


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--check", action="store_true", help="exit 1 when a table differs or lacks its data")
    mode.add_argument("--write", action="store_true", help="rewrite the tables of the pages")
    mode.add_argument("--show", metavar="TABLE", help="print one rendered table")
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                    help="the repository (default: this script's)")
    ap.add_argument("--machine", default=MACHINE, help=f"bench/results/<machine> (default {MACHINE})")
    args = ap.parse_args()
    results = os.path.join(args.root, "bench", "results", args.machine)
    os.chdir(args.root)
    if args.show:
        print(render(args.show, results))
        return 0
    problems = process(args.root, results, args.write)
    if args.check and not problems:
        # The check must be able to fail: the first table, rendered without its data file.
        with tempfile.TemporaryDirectory() as empty:
            name = next(iter(TABLES))
            try:
                render(name, empty)
                problems.append(f"self-check: table {name} rendered without its data file")
            except OSError:
                pass
    for p in problems:
        print(p)
    if problems:
        print(f"render_performance.py: FAILED: {len(problems)} problem(s)")
        return 1
    print(f"render_performance.py: OK: {len(TABLES)} tables of {len(PAGES)} pages match "
          f"bench/results/{args.machine}/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
