#!/usr/bin/env python3
"""d2min_statistics.py [--threshold T] [--gap G] -o OUT.h5 A1.h5 B1.h5 [A2.h5 B2.h5 ...]: the D²min
numbers of thesis Fig. 6.9 as one run's statistics with errors, for the convergence study.

Input: gf-stz d2min maps of one run, in pairs: A_k over a strain interval from a start s_k, B_k
over an interval of the same length later in the same run (the study takes one frame interval from
s_k and one starting two frames later, as Fig. 6.9's (a) 0 → 0.05 and (b) 0.10 → 0.15). Each map is
measured as d2min_maps.py measures it (black grains: D²min per neighbour above T ⟨d⟩², default
d2min_maps.DEFAULT_THRESHOLD; clusters of black grains closer than (R_i + R_j)(1 + G)); per pair
k: the mean over A_k and B_k of the black fraction, the median D²min per neighbour / ⟨d⟩² of the
valid grains, the largest cluster (grains) and the mean cluster size, and the Jaccard index
J(A_k, B_k) with its chance value. Each statistic is the mean over the pairs, its error the
standard error of that mean (the starts are taken far enough apart to be independent; NaN with
one pair).

Output (HDF5, atomically, one row: the run): /parameters (program, script_sha256, command_line,
threshold, gap, pairs, maps (the map files, comma-separated)); /runs/input, input_sha256 (the
trajectory the maps were made from, as they record it: every map must name the same);
/runs/<name> and /runs/<name>_error [1] for black_fraction, d2min_median, largest_cluster,
mean_cluster_size, jaccard, jaccard_chance; /runs/interval [1] (the strain of each map).
"""
import argparse
import math
import os
import shlex
import sys

import h5py
import numpy as np

from analysis import d2min_maps
from granflow import outputs
from granflow.hdf5 import read_attrs, text

STATISTICS = (
    ("black_fraction", "fraction of the valid grains that are black"),
    ("d2min_median", "median D2min per neighbour / mean_diameter^2 of the valid grains"),
    ("largest_cluster", "grains in the largest black cluster"),
    ("mean_cluster_size", "mean grains per black cluster"),
    ("jaccard", "Jaccard index of the black sets of the two maps of a pair"),
    ("jaccard_chance", "Jaccard index of two independent random sets of the same fractions"),
)


def map_source(path):
    """(trajectory, its sha256) a gf-stz d2min map was made from (/parameters input, input_sha256)."""
    with h5py.File(path, "r") as f:
        attrs = read_attrs(f["parameters"]) if "parameters" in f else {}
    if "input" not in attrs:
        raise ValueError(f"{path}: /parameters has no attribute 'input': not a gf-stz d2min output")
    return text(attrs["input"]), text(attrs.get("input_sha256", ""))


def pair_statistics(a, b, threshold, gap):
    """The STATISTICS of one pair of maps (dicts of d2min_maps.read_map)."""
    maps = [a, b]
    pairs = {id(m): d2min_maps.close_pairs(m["position"], m["radius"], m["box"], m["offset"], gap,
                                           d2min_maps.black(m, threshold)) for m in maps}
    _sets, per_map, overlaps = d2min_maps.measure(maps, pairs, threshold)
    values = {name: float(np.mean([r[name] for r in per_map])) for name in
              ("black_fraction", "largest_cluster", "mean_cluster_size")}
    values["d2min_median"] = float(np.mean([np.nanmedian(m["scaled"]) for m in maps]))
    values["jaccard"], values["jaccard_chance"] = overlaps[0]
    return values


def analyse(paths, threshold, gap):
    if len(paths) % 2:
        raise ValueError(f"the maps come in pairs (A, B); got {len(paths)}")
    sources = [map_source(p) for p in paths]
    for path, source in zip(paths[1:], sources[1:]):
        if source[0] != sources[0][0]:
            raise ValueError(f"{path} is of {source[0]}, {paths[0]} of {sources[0][0]}: maps of one run only")
    maps = []
    for path in paths:
        try:
            maps.append(d2min_maps.read_map(path))
        except ValueError as exc:
            raise ValueError(f"{path}: {exc}") from exc
    intervals = {round(m["strain"], 9) for m in maps}
    if len(intervals) != 1:
        raise ValueError(f"the maps span different strain intervals ({sorted(intervals)}): one interval only")
    rows = [pair_statistics(maps[k], maps[k + 1], threshold, gap) for k in range(0, len(maps), 2)]
    result = {}
    for name, _meaning in STATISTICS:
        values = np.array([r[name] for r in rows], dtype=float)
        finite = values[np.isfinite(values)]
        result[name] = float(np.mean(finite)) if len(finite) else math.nan
        result[name + "_error"] = (
            float(np.std(finite, ddof=1) / math.sqrt(len(finite))) if len(finite) > 1 else math.nan
        )
    return sources[0], maps[0]["strain"], len(rows), result


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    d2min_maps.add_black_arguments(ap)
    ap.add_argument("maps", nargs="+", help="gf-stz d2min maps of one run, in pairs A1 B1 A2 B2 ...")
    args = ap.parse_args()
    try:
        d2min_maps.check_black_arguments(args)
        source, interval, pairs, result = analyse(args.maps, args.threshold, args.gap)
    except (ValueError, OSError) as exc:
        print(f"d2min_statistics.py: error: {exc}", file=sys.stderr)
        sys.exit(2)
    parameters = {"threshold": args.threshold, "gap": args.gap, "pairs": pairs, "maps": ",".join(args.maps)}
    with outputs.table(args.output, os.path.abspath(__file__), shlex.join(sys.argv), parameters, [source]) as f:
        runs = f["runs"]
        # Every statistic is a number (D²min is scaled by the mean diameter²).
        outputs.column(runs, "interval", [interval], "1", "strain of each map's interval")
        for name, meaning in STATISTICS:
            outputs.column(runs, name, [result[name]], "1", meaning, dtype=None)
            outputs.column(runs, name + "_error", [result[name + "_error"]], "1",
                           "standard error of the mean over the pairs", dtype=None)


if __name__ == "__main__":
    main()
