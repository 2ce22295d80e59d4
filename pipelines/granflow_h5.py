"""Small helpers shared by the plotting and report scripts: read granflow HDF5 files
and write outputs atomically (temporary name, then rename), like the C++ programs."""
import hashlib
import os
import tempfile

import h5py
import numpy as np


def sha256(path):
    """Hex SHA-256 of a file (the provenance the tables record for their inputs)."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def read_frame(path, frame=-1):
    """Positions, velocities, time, radii, fixed flags, box edges and parameters of one stored frame."""
    with h5py.File(path, "r") as f:
        g = f["/particles/grains"]
        pos = g["position/value"][frame]
        vel = g["velocity/value"][frame]
        time = float(g["position/time"][frame])
        radius = g["radius"][...]
        fixed = g["fixed"][...] if "fixed" in g else np.zeros(len(radius), dtype=np.uint8)
        edges = g["box/edges/value"][frame]
        params = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f["/parameters"].attrs.items()}
    return {"position": pos, "velocity": vel, "time": time, "radius": radius, "fixed": fixed, "edges": edges,
            "parameters": params}


def atomic_output(path):
    """A temporary path beside `path`; call commit() to rename it into place."""
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=directory, prefix="." + os.path.basename(path) + ".part-",
                               suffix=os.path.splitext(path)[1])
    os.close(fd)

    class _Out:
        name = tmp

        @staticmethod
        def commit():
            # mkstemp creates the file 0600; give it the permissions a plain open() would.
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)
            os.replace(tmp, path)

        @staticmethod
        def abandon():
            if os.path.exists(tmp):
                os.remove(tmp)

    return _Out


def save_figure(fig, path, dpi=120):
    """Save a matplotlib figure to `path` atomically."""
    out = atomic_output(path)
    try:
        fig.savefig(out.name, dpi=dpi, bbox_inches="tight")
        out.commit()
    finally:
        out.abandon()
