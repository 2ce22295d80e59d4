#!/usr/bin/env python3
"""CPU hours of a pipeline size, per figure, from the commands make would run.

For each figure or table that `<target>` (default paper-files) writes under FIGURES, asks make
for the exact commands (`make -n` into empty temporary RUNS/FIGURES, with dummy program stamps
so that nothing is built), parses the gf-* command lines and costs every simulation:

  grain-steps = grains x steps. gf-shear: --steps, or --strain / --strain-step (or / |rate|*dt);
  grains from the packing it starts from (gf-pack --grains), a branch (--frame of a run's
  output) inheriting them from its parent. gf-incline: --steps or --time / --time-step, grains
  from the incline start (gf-pack --incline: --grains, or the count gf-pack derives from
  --width, --height and --polydispersity).

  CPU seconds = grain-steps x a measured cost per grain-step:
  - frictionless shear (mu = 0, rate != 0): --frictionless "E=nu:us,..." (microseconds per
    grain-step at N = 10^4 and restitution E; "nu:us,..." alone is E = 0), one table per measured
    restitution, log-linear in nu and flat outside its measured nu; a restitution between two
    measured ones is costed as the range of the two tables' costs, one outside as the nearest;
  - frictional shear: bench/paper_estimate.py's costs and rule (--friction "nu:s_per_strain,..."
    measured at mu = 0.4, e = 0, strain step 1e-3, N = 10^4; an upper bound for mu = 0.1 and
    e = 0.5), converted to a cost per grain-step;
  - unsheared elastic gas (rate 0): --equilibrium "nu:us,...";
  - incline, mu = 0: --incline low:high us; mu > 0 (branches): --incline-friction low:high us;
  - gf-pack: --pack-us-per-grain (biperiodic) and --incline-pack-seconds (one incline start);
  - analyses: frames read x --analysis-ms "program:ms,..." per frame at N = 10^4 (scaled
    linearly in N), every stored frame of each input counted (the windows read fewer; gf-stz
    d2min: the frames it names); the Python tables and plots are not costed (they read the
    tables and observables).

Prints a Markdown table: per figure what it needs, grain-steps, CPU hours (low-high); runs
shared by several figures are listed against each and counted once in the total.
Exit code 2 with one line on stderr for bad input.
"""
import argparse
import math
import os
import re
import shlex
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import paper_estimate  # noqa: E402  (the frictional costs' interpolation and parsing rules)

STAMPED = ["gf-pack", "gf-shear", "gf-correlate", "gf-incline", "gf-kinetic", "gf-network", "gf-stz",
           "libgranflow_statistics.so"]
SIMULATORS = {"gf-pack", "gf-shear", "gf-incline"}
ANALYSERS = {"gf-correlate", "gf-kinetic", "gf-network", "gf-stz"}
# The programs' defaults where an option is absent (their --help).
SHEAR_DEFAULTS = {"--strain": 10.0, "--strain-step": 1e-3, "--rate": 1.0, "--restitution": 0.5,
                  "--friction": 0.0, "--frame-every": None}
INCLINE_DEFAULTS = {"--time": 2000.0, "--time-step": 2e-3, "--restitution": 0.5, "--friction": 0.0}
PACK_DEFAULTS = {"--grains": 1000, "--width": 40.0, "--height": 25.0, "--polydispersity": 0.26}
# Frictional costs are s per strain unit at this strain step and grain count (bench_friction).
FRICTION_STRAIN_STEP, FRICTION_GRAINS = 1e-3, 1e4


class CostError(Exception):
    pass


def fail(message):
    print(f"paper_cost.py: {message}", file=sys.stderr)
    sys.exit(2)


# ------------------------------------------------------------------ parsing make's commands
def _arith(match):
    expr = match.group(1)
    if not re.fullmatch(r"[0-9+\-*/() ]+", expr):
        return match.group(0)
    return str(eval(expr.replace("/", "//"), {"__builtins__": {}}))  # digits and operators only


def logical_lines(text):
    """make -n's output as commands: backslash-newline continuations joined, $((...)) evaluated."""
    text = re.sub(r"\\\n", " ", text)
    text = re.sub(r"\$\(\(([^()]*(?:\([^()]*\)[^()]*)*)\)\)", _arith, text)
    return [line.strip() for line in text.splitlines() if line.strip()]


def parse_command(line):
    """One command line -> dict(program, sub, options, output, input) or None (not gf-* or python)."""
    try:
        words = shlex.split(line)
    except ValueError as error:
        raise CostError(f"cannot split the command line '{line[:60]}...': {error}")
    for k, word in enumerate(words):
        name = os.path.basename(word)
        if name.startswith("gf-") or (name.startswith("python") and k + 1 < len(words)):
            break
    else:
        return None
    program = os.path.basename(words[k])
    rest = words[k + 1:]
    sub = None
    if program.startswith("python"):
        program, sub, rest = "python", os.path.basename(rest[0]), rest[1:]
    elif program == "gf-stz" and rest and not rest[0].startswith("-"):
        sub, rest = rest[0], rest[1:]
    options, positional = {}, []
    k = 0
    while k < len(rest):
        word = rest[k]
        if word.startswith("-") and not re.fullmatch(r"-[0-9.eE+\-,]+", word):
            key = {"-i": "--input", "-o": "--output", "-n": "--grains", "-q": "--quiet"}.get(word, word)
            if "=" in key:
                key, value = key.split("=", 1)
                options[key] = value
            elif k + 1 < len(rest) and (not rest[k + 1].startswith("-")
                                        or re.fullmatch(r"-[0-9.eE+\-,]+", rest[k + 1])):
                options[key] = rest[k + 1]
                k += 1
            else:
                options[key] = True
        else:
            positional.append(word)
        k += 1
    output = options.get("--output")
    if program == "python" and output is None and positional:
        output = positional[-1]
    return {"program": program, "sub": sub, "options": options, "positional": positional,
            "output": output, "input": options.get("--input"), "line": line}


def number(options, key, defaults, kind=float):
    value = options.get(key, defaults.get(key))
    if value is None or value is True:
        raise CostError(f"{key} has no value")
    try:
        return kind(value)
    except ValueError:
        raise CostError(f"{key} '{value}' is not a number")


def incline_pack_grains(options, counted=None):
    """Mobile grains of gf-pack --incline: --grains; a count read from such a start (counted:
    {(width, height): grains}); else lib/packing/incline.cpp's count for --height, 0.8 * width *
    height / (pi <r^2>) with <r^2> = (1 + delta^2/3) / 4, about 1 % low (the base is a little
    longer than --width)."""
    grains = int(number(options, "--grains", {"--grains": 0}))
    if grains > 0:
        return grains
    width = number(options, "--width", PACK_DEFAULTS)
    height = number(options, "--height", PACK_DEFAULTS)
    if counted and (width, height) in counted:
        return counted[(width, height)]
    delta = number(options, "--polydispersity", PACK_DEFAULTS)
    return max(1, round(0.8 * width * height / (math.pi * 0.25 * (1 + delta * delta / 3))))


def parse_runs(text, incline_grains=None):
    """make -n output -> (runs by output path, analyses). A run: program, kind, grains, steps, nu,
    e, mu, input (parent run or packing), frames."""
    runs, analyses = {}, []
    for line in logical_lines(text):
        cmd = parse_command(line)
        if cmd is None:
            continue
        program, opts = cmd["program"], cmd["options"]
        if program in ANALYSERS or program == "python":
            analyses.append(cmd)
            continue
        if program not in SIMULATORS:
            continue
        out = cmd["output"]
        if out is None:
            raise CostError(f"{program} without -o: '{line[:60]}...'")
        run = {"program": program, "output": out, "input": cmd["input"], "frames": 1}
        if program == "gf-pack":
            if "--incline" in opts:
                run.update(kind="incline-pack", grains=incline_pack_grains(opts, incline_grains), steps=0)
            else:
                run.update(kind="pack", grains=int(number(opts, "--grains", PACK_DEFAULTS)), steps=0,
                           nu=number(opts, "--packing-fraction", {"--packing-fraction": 0.8}))
        else:
            parent = runs.get(cmd["input"])
            if parent is None:
                raise CostError(f"{program} reads '{cmd['input']}', which no earlier command makes")
            run["grains"] = parent["grains"]
            run["nu"] = parent.get("nu")
            if program == "gf-shear":
                run.update(_shear_steps(opts))
                run["kind"] = "equilibrium" if run["rate"] == 0 else "shear"
                if parent["kind"] not in ("pack",):
                    run["branch"] = True
            else:
                run.update(_incline_steps(opts))
                run["kind"] = "incline"
                run["branch"] = parent["kind"] == "incline"
            every = opts.get("--frame-every")
            run["frames"] = 1 + run["steps"] // int(every) if every not in (None, True) and int(every) > 0 else 1
        if out in runs:
            raise CostError(f"two commands write '{out}'")
        runs[out] = run
    return runs, analyses


def _shear_steps(opts):
    rate = number(opts, "--rate", SHEAR_DEFAULTS)
    if "--steps" in opts:
        steps = int(number(opts, "--steps", {}))
    elif rate == 0:
        raise CostError("gf-shear at --rate 0 without --steps")
    elif "--dt" in opts:
        steps = round(number(opts, "--strain", SHEAR_DEFAULTS) / (abs(rate) * number(opts, "--dt", {})))
    else:
        steps = round(number(opts, "--strain", SHEAR_DEFAULTS) / number(opts, "--strain-step", SHEAR_DEFAULTS))
    return {"steps": steps, "rate": rate, "e": number(opts, "--restitution", SHEAR_DEFAULTS),
            "mu": number(opts, "--friction", SHEAR_DEFAULTS)}


def _incline_steps(opts):
    if "--steps" in opts:
        steps = int(number(opts, "--steps", {}))
    elif "--dt" in opts:
        raise CostError("gf-incline with --dt (code units) and --time (tau): steps unknown")
    else:
        steps = round(number(opts, "--time", INCLINE_DEFAULTS) / number(opts, "--time-step", INCLINE_DEFAULTS))
    return {"steps": steps, "e": number(opts, "--restitution", INCLINE_DEFAULTS),
            "mu": number(opts, "--friction", INCLINE_DEFAULTS), "angle": number(opts, "--angle", {"--angle": 0})}


# ------------------------------------------------------------------ costs
def parse_range(text, what):
    low, sep, high = text.partition(":")
    try:
        low, high = float(low), float(high if sep else low)
    except ValueError:
        raise CostError(f"{what} '{text}' is not low:high")
    if not 0 < low <= high:
        raise CostError(f"{what} '{text}' is not 0 < low <= high")
    return low, high


def parse_table(text, what):
    table = {}
    for item in text.split(","):
        key, sep, value = item.partition(":")
        try:
            table[float(key)] = float(value)
        except ValueError:
            raise CostError(f"{what}: '{item}' is not nu:cost")
        if table[float(key)] <= 0:
            raise CostError(f"{what}: the cost in '{item}' is not positive")
    return table


def parse_named(text, what):
    table = {}
    for item in filter(None, text.split(",")):
        key, _, value = item.partition(":")
        try:
            table[key] = float(value)
        except ValueError:
            raise CostError(f"{what}: '{item}' is not program:ms")
    return table


class Costs:
    def __init__(self, args):
        self.frictionless = {}
        for text in args.frictionless:
            e, sep, table = text.rpartition("=")
            try:
                e = float(e) if sep else 0.0
            except ValueError:
                raise CostError(f"--frictionless: '{text}' is not E=nu:us,...")
            self.frictionless[e] = parse_table(table, "--frictionless")
        self.friction = parse_table(args.friction, "--friction")
        self.equilibrium = parse_table(args.equilibrium, "--equilibrium")
        self.incline = parse_range(args.incline, "--incline")
        self.incline_friction = parse_range(args.incline_friction, "--incline-friction")
        self.pack_us = args.pack_us_per_grain
        self.incline_pack_s = args.incline_pack_seconds
        self.analysis_ms = parse_named(args.analysis_ms, "--analysis-ms")
        self.incline_grains = {}
        for item in filter(None, args.incline_grains.split(",")):
            size, _, grains = item.partition(":")
            width, _, height = size.partition("x")
            try:
                self.incline_grains[(float(width), float(height))] = int(grains)
            except ValueError:
                raise CostError(f"--incline-grains: '{item}' is not WIDTHxHEIGHT:GRAINS")

    def run_seconds(self, run):
        """(low, high) CPU seconds of one simulation."""
        gs = run["grains"] * run["steps"]
        if run["kind"] == "pack":
            s = run["grains"] * self.pack_us * 1e-6
            return s, s
        if run["kind"] == "incline-pack":
            return self.incline_pack_s, self.incline_pack_s
        if run["kind"] == "incline":
            low, high = self.incline_friction if run["mu"] > 0 else self.incline
            return gs * low * 1e-6, gs * high * 1e-6
        if run["kind"] == "equilibrium":
            s = gs * paper_estimate.cost_at(self.equilibrium, run["nu"]) * 1e-6
            return s, s
        if run["mu"] > 0:
            per_strain = paper_estimate.cost_at(self.friction, run["nu"])
            s = gs * per_strain * FRICTION_STRAIN_STEP / FRICTION_GRAINS
            return s, s
        return tuple(gs * us * 1e-6 for us in self.frictionless_us(run["nu"], run["e"]))

    def frictionless_us(self, nu, e):
        """(low, high) us per grain-step at (nu, e) from the per-restitution tables."""
        measured = sorted(self.frictionless)
        below = [x for x in measured if x <= e + 1e-12]
        above = [x for x in measured if x >= e - 1e-12]
        pair = {below[-1] if below else above[0], above[0] if above else below[-1]}
        costs = [paper_estimate.cost_at(self.frictionless[x], nu) for x in pair]
        return min(costs), max(costs)

    def analysis_seconds(self, cmd, runs):
        program = cmd["program"] + (" " + cmd["sub"] if cmd["sub"] else "")
        if program not in self.analysis_ms:
            return 0.0
        frames = 0
        if "--frames" in cmd["options"]:  # gf-stz d2min reads the frames it names
            source = runs.get(cmd["input"])
            return len(cmd["options"]["--frames"].split(",")) * (source["grains"] / 1e4 if source else 1) \
                * self.analysis_ms[program] * 1e-3
        for word in cmd["positional"] + [v for v in cmd["options"].values() if isinstance(v, str)]:
            for path in word.split(","):
                if path in runs and runs[path]["kind"] not in ("pack", "incline-pack"):
                    frames += runs[path]["frames"] * runs[path]["grains"] / 1e4
        return frames * self.analysis_ms[program] * 1e-3


# ------------------------------------------------------------------ make
def make_dry_run(repo, size, target, tmp, bin_dir="bin"):
    stamps = os.path.join(tmp, "stamps")
    os.makedirs(stamps, exist_ok=True)
    for name in STAMPED:
        open(os.path.join(stamps, name + ".stamp"), "a").close()
    command = ["make", "--no-print-directory", "-C", repo, "-f", "Makefile.sweeps", f"SIZE={size}",
               f"RUNS={tmp}/runs", f"FIGURES={tmp}/figures", f"STAMPS={stamps}", f"BIN={bin_dir}", "-n", target]
    out = subprocess.run(command, capture_output=True, text=True)
    if out.returncode != 0:
        last = (out.stderr.strip().splitlines() or ["(no message)"])[-1]
        raise CostError(f"make -n {target} failed: {last}")
    return out.stdout


def figure_targets(text, figures_dir):
    """The files under FIGURES that the commands name (a plot's output is not always its last
    argument), in order of first mention."""
    seen = []
    for line in logical_lines(text):
        cmd = parse_command(line)
        if cmd is None:
            continue
        for word in cmd["positional"] + [v for v in cmd["options"].values() if isinstance(v, str)]:
            if word.startswith(figures_dir + "/") and word.rstrip("/") != figures_dir and word not in seen:
                seen.append(word)
    return seen


def kind_of(run):
    if run["kind"] in ("pack", "incline-pack"):
        return "packings" if run["kind"] == "pack" else "incline starts"
    friction = " (μ > 0)" if run["mu"] > 0 else ""
    if run["kind"] == "shear":
        return ("shear branches" if run.get("branch") else "shear runs") + friction
    if run["kind"] == "equilibrium":
        return "equilibrium runs"
    return ("incline branches" if run.get("branch") else "incline runs") + friction


def by_kind(runs):
    groups = {}
    for run in runs.values():
        groups.setdefault(kind_of(run), []).append(run)
    return groups


def describe(runs):
    """'37 shear runs (μ > 0), N = 10000; ...' for a set of simulations."""
    parts = []
    for key, group in by_kind(runs).items():
        sizes = sorted(set(r["grains"] for r in group))
        size = f"N = {sizes[0]}" if len(sizes) == 1 else f"N = {sizes[0]}–{sizes[-1]}"
        if len(group) == 1:
            for plural, singular in (("runs", "run"), ("starts", "start"), ("packings", "packing"), ("branches", "branch")):
                key = key.replace(plural, singular)
        parts.append(f"{len(group)} {key}, {size}")
    return "; ".join(parts) if parts else "none"


def hours(pair):
    low, high = (x / 3600 for x in pair)
    fmt = (lambda x: f"{x:.0f}") if high >= 10 else (lambda x: f"{x:.1f}") if high >= 0.1 else (lambda x: f"{x:.2f}")
    return fmt(low) if fmt(low) == fmt(high) else f"{fmt(low)}–{fmt(high)}"


def cost_of(runs, analyses, costs, all_runs):
    sim = [sum(x) for x in zip(*(costs.run_seconds(r) for r in runs.values()))] or [0.0, 0.0]
    ana = sum(costs.analysis_seconds(a, all_runs) for a in analyses)
    grain_steps = sum(r["grains"] * r["steps"] for r in runs.values())
    return grain_steps, sim, ana


def chains(runs, costs):
    """Per run: (low, high) CPU seconds of the longest chain of simulations ending with it."""
    done = {}

    def chain(path):
        if path not in done:
            run = runs[path]
            own = costs.run_seconds(run)
            before = chain(run["input"]) if run.get("input") in runs else (0.0, 0.0)
            done[path] = (own[0] + before[0], own[1] + before[1])
        return done[path]
    for path in runs:
        chain(path)
    return done


def report(repo, size, target, costs, tmp):
    text = make_dry_run(repo, size, target, tmp)
    all_runs, all_analyses = parse_runs(text, costs.incline_grains)
    figures_dir = f"{tmp}/figures"
    rows = []
    for figure in figure_targets(text, figures_dir):
        runs, analyses = parse_runs(make_dry_run(repo, size, figure, tmp), costs.incline_grains)
        grain_steps, sim, ana = cost_of(runs, analyses, costs, all_runs)
        name = os.path.relpath(figure, tmp)
        rows.append((name, describe(runs), grain_steps, sim, ana))
    grain_steps, sim, ana = cost_of(all_runs, all_analyses, costs, all_runs)
    lines = [f"Size {size}, target {target}: CPU hours of one core (low–high where a cost is a range).", "",
             "| figure | needs | grain-steps | simulations, CPU h | analyses, CPU h |", "|---|---|---|---|---|"]
    for name, needs, gs, s, a in rows:
        lines.append(f"| {name} | {needs} | {gs:.2g} | {hours(s)} | {hours((a, a))} |")
    lines.append(f"| **{target}** (each run once) | {describe(all_runs)} | {grain_steps:.2g} | **{hours(sim)}** | "
                 f"{hours((ana, ana))} |")
    lines += ["", "| simulations of the total, by kind | runs | grain-steps | CPU h |", "|---|---|---|---|"]
    for key, group in by_kind(all_runs).items():
        cost = [sum(x) for x in zip(*(costs.run_seconds(r) for r in group))]
        lines.append(f"| {key} | {len(group)} | {sum(r['grains'] * r['steps'] for r in group):.2g} | {hours(cost)} |")
    sims = {p: r for p, r in all_runs.items() if r["kind"] not in ("pack", "incline-pack")}
    longest = max(sims, key=lambda p: costs.run_seconds(sims[p])[1])
    chain = chains(all_runs, costs)
    deepest = max(chain, key=lambda p: chain[p][1])
    independent = sum(1 for r in sims.values() if all_runs.get(r["input"], {}).get("kind") in ("pack", "incline-pack"))
    lines += ["",
              f"Simulations: {len(sims)} (and {len(all_runs) - len(sims)} packings). Longest single run: "
              f"{os.path.basename(longest)}, {hours(costs.run_seconds(sims[longest]))} CPU h. Longest chain of runs "
              f"(a branch after its parent): ending in {os.path.basename(deepest)}, {hours(chain[deepest])} CPU h. "
              f"Runs that can start together once the packings exist: {independent}; the other "
              f"{len(sims) - independent} wait for their parent run."]
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repo", default=os.path.dirname(HERE), help="the granflow tree (Makefile.sweeps)")
    parser.add_argument("--size", default="paper", choices=["quick", "paper", "test"])
    parser.add_argument("--target", default="paper-files")
    parser.add_argument("--frictionless", required=True, action="append",
                        help="E=nu:us per grain-step,... (mu = 0 shear, N = 10^4, restitution E; repeat per E)")
    parser.add_argument("--friction", required=True, help="nu:s per strain,... (mu = 0.4, e = 0, N = 10^4)")
    parser.add_argument("--equilibrium", required=True, help="nu:us per grain-step,... (rate 0, e = 1)")
    parser.add_argument("--incline", required=True, help="low:high us per grain-step, mu = 0")
    parser.add_argument("--incline-friction", required=True, help="low:high us per grain-step, mu > 0 branches")
    parser.add_argument("--pack-us-per-grain", type=float, default=100.0, help="gf-pack, biperiodic")
    parser.add_argument("--incline-pack-seconds", type=float, default=1.0, help="gf-pack --incline, one start")
    parser.add_argument("--incline-grains", default="", help="WIDTHxHEIGHT:GRAINS,... mobile grains counted in "
                        "gf-pack --incline starts (else the count is computed, ~1 %% low)")
    parser.add_argument("--analysis-ms", default="gf-correlate:28,gf-kinetic:7,gf-network:7,gf-stz fit:7,"
                        "gf-stz d2min:110", help="program:ms per frame read at N = 10^4,...")
    args = parser.parse_args(argv)
    try:
        if not os.path.isfile(os.path.join(args.repo, "Makefile.sweeps")):
            raise CostError(f"no Makefile.sweeps in '{args.repo}'")
        costs = Costs(args)
        with tempfile.TemporaryDirectory(prefix="paper_cost.") as tmp:
            print(report(args.repo, args.size, args.target, costs, tmp))
    except CostError as error:
        fail(str(error))


if __name__ == "__main__":
    main()
