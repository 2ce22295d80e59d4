#!/usr/bin/python3
"""Tiles the last frame of a sheared run K x K times into a packing file gf-shear reads.

    tile_packing.py PACKING.h5 RUN.h5 K OUT.h5

PACKING.h5 is the gf-pack file RUN.h5 (a gf-shear run from it) started from; OUT.h5 is a copy
of it whose grains are those of RUN.h5's last frame repeated on a K x K grid of cells: K² times
the grains in a box K times wider and taller, at the same packing fraction, and numbered band
by band (bands of one mean diameter, by x within a band), as gf-pack numbers them. The last
frame's Lees-Edwards offset must be a whole number of box widths (a square box at a whole
strain), so that the tiles meet as the frame's own periodic images do.

Why (docs/performance.md, "A million grains"): gf-shear's first steps from a gf-pack packing,
where every neighbouring pair touches, solve one cluster of active contacts spanning the box;
its factorisation costs more than linearly in N, and at 10^6 grains the start takes hours on
one core. A sheared structure tiled to 10^6 grains starts the timed run near the steady flow
for the cost of a 10^4-grain warm-up. The copy's velocities and spins are zero (gf-shear's
affine start replaces them); its tiles are copies, so correlations longer than the tile's side
are those of the tiling until the flow has mixed them.
"""
import sys

import h5py
import numpy as np

PER_GRAIN = ["radius", "mass", "fixed"]
PER_GRAIN_FRAME = ["position", "velocity", "orientation", "angular_velocity"]


def main(argv):
    if len(argv) != 5:
        sys.stderr.write(__doc__)
        return 2
    packing, run, k, out = argv[1], argv[2], int(argv[3]), argv[4]
    if k < 1:
        sys.stderr.write("tile_packing.py: K must be >= 1\n")
        return 2
    with h5py.File(run, "r") as r:
        g = r["particles/grains"]
        pos = g["position/value"][-1]
        edges = g["box/edges/value"][-1]
        offset = float(r["lees_edwards/offset/value"][-1]) if "lees_edwards/offset/value" in r else 0.0
        radius = g["radius"][()]
        mass = g["mass"][()]
        fixed = g["fixed"][()]
    lx, ly = float(edges[0][0]), float(edges[1][1])
    shift = offset - lx * round(offset / lx)
    if abs(shift) > 1e-9 * lx:
        sys.stderr.write(f"tile_packing.py: offset {offset} is not a whole number of box widths {lx}\n")
        return 2
    n = len(radius)
    ix, iy = np.meshgrid(np.arange(k), np.arange(k), indexing="ij")
    ix, iy = ix.ravel(), iy.ravel()
    wrapped = np.column_stack([np.mod(pos[:, 0], lx), np.mod(pos[:, 1], ly)])
    big = np.concatenate([wrapped + np.array([a * lx, b * ly]) for a, b in zip(ix, iy)])
    rad = np.tile(radius, k * k)
    band = np.floor(big[:, 1] / (2 * radius.mean())).astype(np.int64)
    order = np.lexsort((big[:, 0], band))
    big, rad = big[order], rad[order]
    mass_t, fixed_t = np.tile(mass, k * k)[order], np.tile(fixed, k * k)[order]
    m = n * k * k
    with h5py.File(packing, "r") as src, h5py.File(out, "w") as dst:
        for key, value in src.attrs.items():
            dst.attrs[key] = value
        for name in src:
            src.copy(src[name], dst, name=name)
        g = dst["particles/grains"]
        for name, data in (("radius", rad), ("mass", mass_t), ("fixed", fixed_t)):
            old = g[name]
            dtype, attrs = old.dtype, dict(old.attrs)
            del g[name]
            ds = g.create_dataset(name, data=data.astype(dtype))
            for key, value in attrs.items():
                ds.attrs[key] = value
        for name in PER_GRAIN_FRAME:
            old = g[name + "/value"]
            dtype, attrs = old.dtype, dict(old.attrs)
            shape = (1, m) + old.shape[2:]
            del g[name + "/value"]
            data = big.reshape(shape) if name == "position" else np.zeros(shape, dtype)
            ds = g[name].create_dataset("value", data=data.astype(dtype), maxshape=(None,) + shape[1:],
                                        chunks=(1,) + shape[1:], compression="gzip")
            for key, value in attrs.items():
                ds.attrs[key] = value
        e = g["box/edges/value"]
        e[...] = e[...] * k
        dst["parameters"].attrs["grains"] = m
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
