#!/usr/bin/env python3
"""d2min_maps.py [--threshold T] [--gap G] [--start-strain S,S,...] -o MAPS.h5 MAP.h5...: the numbers
of thesis Fig. 6.9 from gf-stz d2min outputs (the first map is the one the others are compared
with: (a) 0 → 0.05, (b) 0.10 → 0.15, (c) 0 → 0.15, (d) 0 → −0.05).

Black grains: D²min per neighbour (/d2min/per_neighbour, the sum over the neighbours divided by
their number) above T ⟨d⟩², ⟨d⟩ the map's mean diameter (/d2min attribute mean_diameter).
Per neighbour and not the sum: the sum grows with the number of neighbours inside the cutoff,
so a grain would turn black for having more neighbours; per neighbour it is the mean squared
mismatch of a bond from its best affine image, √(T) ⟨d⟩ its rms. Default T = 1e-2: a bond
off its affine image by 0.1 ⟨d⟩ rms, twice the affine change of a bond one diameter long over
the strain 0.05 of maps (a), (b), (d); in the quick size's maps (ν = 0.80, e = 0) the median
grain is at 3.3-3.8e-3 and T = 1e-2 marks the tail of 7-8 % of the grains. The thesis gives no
value ("larger than a reference value"): the same numbers over a sweep of thresholds,
T·10^(k/4) for k = −4..4 (two decades), show what depends on it. Grains whose fit is singular (/d2min/valid 0) are never
black, and fractions count the valid grains only.

Clusters: two black grains are joined when their centres in the map's reference frame are
closer than (R_i + R_j)(1 + G) (default G = 0.1: in contact or nearly, the contact neighbours of
a dense packing), by the Lees–Edwards minimum image of the reference frame (/reference: box
L_x, L_y and offset δ; an image one period up is shifted by +δ in x); clusters are the
connected components.

Overlap of the first map's black set A with each other map's B: the Jaccard index
J = |A ∩ B| / |A ∪ B| over the grains valid in both, and the value expected for two
independent random sets of the same fractions p, q of those grains, pq / (p + q − pq) (the
ratio of the expected intersection and union), so that an overlap can be compared with chance.
NaN when both sets are empty.

Output (HDF5, atomically): /parameters (program, script_sha256, command_line, threshold, gap,
sweep); /runs/input, input_sha256 (the maps, in order); /maps/<column> [M] (label a, b, ...,
strain, start_strain, end_strain, reference_frame, current_frame, current_source, grains,
valid_count, mean_diameter, offset), /maps/box [M, 2], /maps/position [M, N, 2],
/maps/radius [M, N] (the reference frames), /maps/d2min_scaled [M, N] (D²min per neighbour /
⟨d⟩², NaN where invalid), /maps/black [M, N] uint8 (at T); /default/{black_count,
black_fraction, cluster_count, largest_cluster, mean_cluster_size} [M],
/default/cluster_size_histogram [M, S] (number of clusters of s + 1 grains),
/default/{pair, jaccard, jaccard_chance} [M − 1] (pair "a-b", ...), attribute threshold;
/sweep/threshold [K], /sweep/{black_fraction, cluster_count, largest_cluster,
mean_cluster_size} [M, K], /sweep/{jaccard, jaccard_chance} [M − 1, K].
"""
import argparse
import math
import os
import shlex
import sys

import h5py
import numpy as np

from granflow import outputs
from granflow.hdf5 import read_attrs, sha256, text

DEFAULT_THRESHOLD = 1e-2
DEFAULT_GAP = 0.1
# The sweep: threshold · 10^(k/4), k = −4 … 4.
SWEEP_EXPONENTS = np.arange(-4, 5) / 4.0
# Per-map columns of /maps: (unit, meaning).
MAP_COLUMNS = {
    "strain": ("1", "strain from the reference to the current frame (/d2min attribute strain)"),
    "start_strain": ("1", "strain at the reference frame, as given by --start-strain"),
    "end_strain": ("1", "start_strain + strain"),
    "reference_frame": ("1", "index of the reference frame (-1: not recorded)"),
    "current_frame": ("1", "index of the current frame (-1: not recorded)"),
    "grains": ("1", "grains in the map"),
    "valid_count": ("1", "grains whose fit is not singular"),
    "mean_diameter": ("L", "⟨d⟩, the map's mean diameter"),
    "offset": ("L", "the reference frame's Lees–Edwards offset δ"),
}
# The per-map statistics of /default and /sweep.
STATISTIC_MEANINGS = {
    "black_count": "black grains",
    "black_fraction": "fraction of the valid grains that are black",
    "cluster_count": "black clusters",
    "largest_cluster": "grains in the largest black cluster",
    "mean_cluster_size": "mean grains per black cluster",
    "jaccard": "Jaccard index of the first map's black set and this map's",
    "jaccard_chance": "the Jaccard index of independent random sets of the same fractions",
}


def read_map(path):
    """One gf-stz d2min output: a dict of its per-grain arrays and attributes. Raises ValueError
    (naming what is missing or inconsistent) for a file that is not one."""
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise ValueError(f"cannot open as HDF5 ({exc})") from exc
    with f:
        for name in (
            "d2min/per_neighbour",
            "d2min/valid",
            "d2min/neighbours",
            "reference/position",
            "reference/radius",
        ):
            if name not in f:
                raise ValueError(f"no /{name}: not a gf-stz d2min output")
        d, ref = f["d2min"], f["reference"]
        m = {
            "per_neighbour": np.asarray(d["per_neighbour"], dtype=float),
            "valid": np.asarray(d["valid"]).astype(bool),
            "position": np.asarray(ref["position"], dtype=float),
            "radius": np.asarray(ref["radius"], dtype=float),
        }
        attrs, ref_attrs = read_attrs(d), read_attrs(ref)
    n = len(m["radius"])
    if m["position"].shape != (n, 2) or m["per_neighbour"].shape != (n,) or m["valid"].shape != (n,):
        raise ValueError(
            f"/d2min and /reference disagree in shape ({m['per_neighbour'].shape}, {m['valid'].shape}, "
            f"{m['position'].shape}, radius {n})"
        )
    if n == 0:
        raise ValueError("no grains")
    for key in ("box", "offset"):
        if key not in ref_attrs:
            raise ValueError(f"/reference has no attribute '{key}'")
    box = np.asarray(ref_attrs["box"], dtype=float).ravel()
    if box.shape != (2,) or not np.all(box > 0):
        raise ValueError(f"/reference attribute box is not two positive lengths: {box}")
    m["box"], m["offset"] = box, float(ref_attrs["offset"])
    if "strain" not in attrs:
        raise ValueError("/d2min has no attribute 'strain'")
    m["strain"] = float(attrs["strain"])
    diameter = attrs.get("mean_diameter")
    m["mean_diameter"] = float(diameter) if diameter is not None else 2 * float(np.mean(m["radius"]))
    m["reference_frame"] = int(attrs.get("reference_frame", -1))
    m["current_frame"] = int(attrs.get("current_frame", -1))
    m["current_source"] = text(attrs.get("current_source", ""))
    m["grains"] = n
    m["valid_count"] = int(np.sum(m["valid"]))
    m["scaled"] = np.where(m["valid"], m["per_neighbour"] / m["mean_diameter"] ** 2, np.nan)
    return m


def black(m, threshold):
    """Valid grains whose D²min per neighbour exceeds threshold · ⟨d⟩² (NaN never does)."""
    with np.errstate(invalid="ignore"):
        return m["valid"] & (m["scaled"] > threshold)


def close_pairs(position, radius, box, offset, gap, candidates):
    """(i, j) index arrays, i < j, of the candidate grains whose centres are closer than
    (R_i + R_j)(1 + gap), Lees–Edwards minimum image (offset δ of the row one period up)."""
    idx = np.flatnonzero(candidates)
    lx, ly = box
    pi, pj = [], []
    chunk = 512
    for start in range(0, len(idx), chunk):
        rows = idx[start : start + chunk]
        dx = position[idx, 0][None, :] - position[rows, 0][:, None]
        dy = position[idx, 1][None, :] - position[rows, 1][:, None]
        ky = np.round(dy / ly)
        dy -= ky * ly
        dx -= ky * offset
        dx -= lx * np.round(dx / lx)
        reach = (radius[rows][:, None] + radius[idx][None, :]) * (1 + gap)
        a, b = np.nonzero((dx * dx + dy * dy < reach * reach) & (rows[:, None] < idx[None, :]))
        pi.append(rows[a])
        pj.append(idx[b])
    if not pi:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    return np.concatenate(pi), np.concatenate(pj)


def cluster_sizes(selected, pairs):
    """Sizes of the connected components of the selected grains joined by the pairs whose two
    grains are both selected (minimum-label propagation with pointer jumping)."""
    n = len(selected)
    i, j = pairs
    keep = selected[i] & selected[j]
    i, j = i[keep], j[keep]
    label = np.arange(n)
    while True:
        low = np.minimum(label[i], label[j])
        new = label.copy()
        np.minimum.at(new, i, low)
        np.minimum.at(new, j, low)
        new = new[new]
        if np.array_equal(new, label):
            break
        label = new
    return np.bincount(np.unique(label[selected], return_inverse=True)[1]) if selected.any() else np.zeros(0, int)


def jaccard(a, b, valid):
    """(J, chance) of the black sets a, b over the grains valid in both."""
    a, b = a & valid, b & valid
    union = int(np.sum(a | b))
    n = int(np.sum(valid))
    if union == 0 or n == 0:
        return math.nan, math.nan
    p, q = np.sum(a) / n, np.sum(b) / n
    return float(np.sum(a & b)) / union, float(p * q / (p + q - p * q))


def measure(maps, pairs, threshold):
    """The numbers of one threshold: per map (black count, fraction, cluster sizes) and the
    Jaccard index of the first map with each other one."""
    sets = [black(m, threshold) for m in maps]
    per_map = []
    for m, s in zip(maps, sets):
        sizes = cluster_sizes(s, pairs[id(m)])
        count = int(np.sum(s))
        per_map.append(
            {
                "black_count": count,
                "black_fraction": count / m["valid_count"] if m["valid_count"] else math.nan,
                "cluster_count": len(sizes),
                "largest_cluster": int(sizes.max()) if len(sizes) else 0,
                "mean_cluster_size": float(sizes.mean()) if len(sizes) else math.nan,
                "sizes": sizes,
            }
        )
    overlaps = [jaccard(sets[0], s, maps[0]["valid"] & m["valid"]) for m, s in zip(maps[1:], sets[1:])]
    return sets, per_map, overlaps


def analyse(paths, threshold, gap, start_strains):
    maps = []
    for path in paths:
        try:
            maps.append(read_map(path))
        except ValueError as exc:
            raise ValueError(f"{path}: {exc}") from exc
    for path, m in zip(paths[1:], maps[1:]):
        if m["grains"] != maps[0]["grains"]:
            raise ValueError(f"{path}: {m['grains']} grains, {paths[0]} has {maps[0]['grains']}: not the same grains")
    for m, s in zip(maps, start_strains):
        m["start_strain"] = s
        m["end_strain"] = s + m["strain"]
    thresholds = threshold * 10.0**SWEEP_EXPONENTS
    lowest = min(thresholds.min(), threshold)
    # Black sets shrink as the threshold grows: the pairs among the grains black at the lowest
    # threshold serve every threshold.
    pairs = {id(m): close_pairs(m["position"], m["radius"], m["box"], m["offset"], gap, black(m, lowest)) for m in maps}
    default = measure(maps, pairs, threshold)
    sweep = [measure(maps, pairs, t)[1:] for t in thresholds]
    return maps, thresholds, default, sweep


def write(output, paths, maps, threshold, gap, thresholds, default, sweep, command_line):
    labels = [chr(ord("a") + k) for k in range(len(maps))]
    with outputs.table(
        output,
        os.path.abspath(__file__),
        command_line,
        {
            "threshold": threshold,
            "gap": gap,
            "quantity": "D2min per neighbour / mean_diameter^2 (/d2min/per_neighbour)",
            "sweep": "threshold * 10^(k/4), k = -4..4",
        },
        [(p, sha256(p)) for p in paths],
    ) as f:
        g = f.create_group("maps")
        outputs.text_dataset(g, "label", labels)
        outputs.text_dataset(g, "current_source", [m["current_source"] for m in maps])
        for col, (unit, meaning) in MAP_COLUMNS.items():
            outputs.column(g, col, [m[col] for m in maps], unit, meaning, dtype=None)
        outputs.column(g, "box", [m["box"] for m in maps], "L", "[map, 2]: the reference frame's box L_x, L_y")
        outputs.column(g, "position", [m["position"] for m in maps], "L", "[map, grain, 2]: centres in the reference frame")
        outputs.column(g, "radius", [m["radius"] for m in maps], "L", "[map, grain]: radii")
        outputs.column(g, "d2min_scaled", [m["scaled"] for m in maps], "1",
                       "[map, grain]: D²min per neighbour / ⟨d⟩², NaN where the fit is singular")
        sets, per_map, overlaps = default
        outputs.column(g, "black", sets, "1", "[map, grain]: 1 if the grain is black at the threshold", dtype=np.uint8)
        d = f.create_group("default")
        d.attrs["threshold"] = threshold
        for name in ("black_count", "black_fraction", "cluster_count", "largest_cluster", "mean_cluster_size"):
            outputs.column(d, name, [r[name] for r in per_map], "1", f"[map]: {STATISTIC_MEANINGS[name]}", dtype=None)
        width = max([1] + [len(r["sizes"]) and int(r["sizes"].max()) for r in per_map])
        hist = np.zeros((len(maps), width), dtype=np.int64)
        for k, r in enumerate(per_map):
            if len(r["sizes"]):
                hist[k, : int(r["sizes"].max())] = np.bincount(r["sizes"])[1:]
        outputs.column(d, "cluster_size_histogram", hist, "1", "[map, s]: number of black clusters of s + 1 grains",
                       dtype=np.int64)
        outputs.text_dataset(d, "pair", [f"a-{x}" for x in labels[1:]])
        for k, name in enumerate(("jaccard", "jaccard_chance")):
            outputs.column(d, name, [o[k] for o in overlaps], "1", f"[pair]: {STATISTIC_MEANINGS[name]}")
        s = f.create_group("sweep")
        outputs.column(s, "threshold", thresholds, "1", "[K]: the thresholds swept, in ⟨d⟩²")
        for name in ("black_fraction", "cluster_count", "largest_cluster", "mean_cluster_size"):
            outputs.column(s, name, [[t[0][k][name] for t in sweep] for k in range(len(maps))], "1",
                           f"[map, K]: {STATISTIC_MEANINGS[name]}", dtype=None)
        for k, name in enumerate(("jaccard", "jaccard_chance")):
            outputs.column(s, name, [[t[1][p][k] for t in sweep] for p in range(len(maps) - 1)], "1",
                           f"[pair, K]: {STATISTIC_MEANINGS[name]}")


def read_table(path):
    """{group: {name: values}} of a maps table, plus "parameters"."""
    table = outputs.read_table(path, ("runs", "maps", "default", "sweep"))
    with h5py.File(path, "r") as f:
        table["default"]["threshold"] = float(f["default"].attrs["threshold"])
    return table


def strains(text_value, count):
    items = [s for s in text_value.split(",")] if text_value else ["0"] * count
    if len(items) != count:
        raise ValueError(f"--start-strain has {len(items)} values for {count} maps")
    try:
        return [float(s) for s in items]
    except ValueError as exc:
        raise ValueError(f"--start-strain: {exc}") from exc


def add_black_arguments(ap):
    """The options of a script that measures maps: --threshold, --gap, -o and the maps."""
    ap.add_argument("--threshold", type=float, default=DEFAULT_THRESHOLD,
                    help=f"black: D2min per neighbour above this times <d>^2 ({DEFAULT_THRESHOLD:g})")
    ap.add_argument("--gap", type=float, default=DEFAULT_GAP,
                    help=f"clusters: centres closer than (Ri+Rj)(1+gap) ({DEFAULT_GAP:g})")
    ap.add_argument("-o", "--output", required=True)


def check_black_arguments(args):
    """ValueError naming the option when --threshold, --gap or -o (one of the maps) is bad."""
    if not (args.threshold > 0 and math.isfinite(args.threshold)):
        raise ValueError(f"--threshold must be positive (got {args.threshold:g})")
    if not (args.gap >= 0 and math.isfinite(args.gap)):
        raise ValueError(f"--gap must be 0 or more (got {args.gap:g})")
    if os.path.abspath(args.output) in {os.path.abspath(p) for p in args.maps}:
        raise ValueError(f"--output {args.output} is one of the inputs")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_black_arguments(ap)
    ap.add_argument("--start-strain", default="", help="strain at each map's reference frame, comma-separated (0)")
    ap.add_argument("maps", nargs="+", help="gf-stz d2min outputs; the first is compared with the others")
    args = ap.parse_args()
    try:
        check_black_arguments(args)
        starts = strains(args.start_strain, len(args.maps))
        maps, thresholds, default, sweep = analyse(args.maps, args.threshold, args.gap, starts)
    except ValueError as exc:
        print(f"d2min_maps.py: error: {exc}", file=sys.stderr)
        sys.exit(2)
    write(args.output, args.maps, maps, args.threshold, args.gap, thresholds, default, sweep, shlex.join(sys.argv))


if __name__ == "__main__":
    main()
