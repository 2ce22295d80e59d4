#!/usr/bin/env python3
"""Estimate the CPU hours of SIZE=paper's frictional runs from measured costs.

Shear runs (N = 10^4): each run of the paper grid is costed at the CPU seconds per strain unit
that bench_friction measured at mu = 0.4, e = 0 (--before / --after: "nu:seconds" pairs),
interpolated log-linearly in nu, at the lowest measured nu's cost below it and at the highest
one's above. e = 0.5 and mu = 0.1 runs are costed as mu = 0.4, e = 0, which is an upper bound.

Incline branches: grain-steps times a cost per grain-step (--incline-before / --incline-after:
"low:high" in microseconds, from the quick branches).

The grids are pipelines/sizes/paper.mk's: Fig. 5.4 at mu = 0.1 and 0.4, e = 0; Fig. 4.10 at
mu = 0.4, e = 0.5; runs at nu <= 0.70 are 80 strain units long, denser ones 20. Inclines:
5 branches at e = 0.5 (Fig. 4.10) and 3 at e = 0 (section 6.3), 1000 tau at 2e-3 tau, about
5000 grains.
"""
import argparse
import math
import sys


def fail(message):
    print(f"paper_estimate.py: {message}", file=sys.stderr)
    sys.exit(2)

LONG_NU = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.65, 0.70]
DENSE_NU = [0.72, 0.74, 0.76, 0.77, 0.78, 0.79, 0.80]
FIG410_NU = [0.70, 0.74, 0.76, 0.77, 0.78, 0.79, 0.80]
LONG_STRAIN, DENSE_STRAIN = 80, 20
INCLINE_BRANCHES, INCLINE_STEPS, INCLINE_GRAINS = 8, 1000 / 2e-3, 5000


def parse_costs(text):
    costs = {}
    for item in text.split(","):
        nu, _, seconds = item.partition(":")
        try:
            costs[float(nu)] = float(seconds)
        except ValueError:
            fail(f"'{item}' is not nu:seconds")
        if costs[float(nu)] <= 0:
            fail(f"the cost in '{item}' is not positive")
    return costs


def parse_range(text):
    low, _, high = text.partition(":")
    try:
        return float(low), float(high)
    except ValueError:
        fail(f"'{text}' is not low:high")


def cost_at(costs, nu):
    xs = sorted(costs)
    if nu <= xs[0]:
        return costs[xs[0]]
    for a, b in zip(xs, xs[1:]):
        if nu <= b:
            f = (nu - a) / (b - a)
            return math.exp((1 - f) * math.log(costs[a]) + f * math.log(costs[b]))
    return costs[xs[-1]]


def shear_runs():
    runs = []
    for _mu in (0.1, 0.4):
        runs += [(nu, LONG_STRAIN) for nu in LONG_NU] + [(nu, DENSE_STRAIN) for nu in DENSE_NU]
    runs += [(nu, LONG_STRAIN if nu <= 0.70 else DENSE_STRAIN) for nu in FIG410_NU]
    return runs


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--before", required=True, help="nu:s_per_strain,... of the previous solver")
    parser.add_argument("--after", required=True, help="nu:s_per_strain,... of the current solver")
    parser.add_argument("--incline-before", required=True, help="low:high microseconds per grain-step")
    parser.add_argument("--incline-after", required=True, help="low:high microseconds per grain-step")
    args = parser.parse_args()
    cases = [(name, parse_costs(costs), parse_range(incline)) for name, costs, incline in
             (("before", args.before, args.incline_before), ("after", args.after, args.incline_after))]
    runs = shear_runs()
    grain_steps = INCLINE_BRANCHES * INCLINE_STEPS * INCLINE_GRAINS
    print(f"{len(runs)} shear runs at N = 10^4; {INCLINE_BRANCHES} incline branches, {grain_steps:.2g} grain-steps")
    for name, costs, incline in cases:
        shear = sum(cost_at(costs, nu) * strain for nu, strain in runs) / 3600
        dense = sum(cost_at(costs, nu) * strain for nu, strain in runs if nu >= 0.79) / 3600
        low, high = (grain_steps * us * 1e-6 / 3600 for us in incline)
        print(f"{name}: shear {shear:.0f} CPU h (nu >= 0.79: {dense:.0f}), inclines {low:.0f}-{high:.0f} CPU h, "
              f"together {shear + low:.0f}-{shear + high:.0f} CPU h")


if __name__ == "__main__":
    main()
