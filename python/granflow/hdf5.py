"""Reading granflow's HDF5 files: strings as text, attributes, whole groups of datasets, one
stored frame of grains (through granflow.trajectory), times in τ whatever unit a file stores
them in; and the SHA-256 every table records for its inputs."""
import hashlib

import h5py
import numpy as np


def text(value):
    """An HDF5 string as str (h5py returns variable-length strings as bytes); anything else as is."""
    return value.decode() if isinstance(value, bytes) else value


def read_attrs(obj):
    """The attributes of an HDF5 group or dataset, strings as text."""
    return {k: text(v) for k, v in obj.attrs.items()}


# The H5MD unit of the code time (docs/file-format.md, Units); files written before the
# units module said "code".
CODE_TIME_UNITS = ("T", "code")


def time_unit(ds):
    """The unit of an H5MD time dataset: its `unit` attribute ("tau" in gf-incline's
    trajectories, "T", the code time, in the others; "code" in files before the units
    module); "T" where the attribute is absent."""
    return text(ds.attrs.get("unit", "T"))


def in_tau(time, unit, tau):
    """Times stored in `unit` ("tau", or the code time "T" or "code") in units of τ (tau: τ
    in code time)."""
    if unit == "tau":
        return time
    if unit in CODE_TIME_UNITS:
        return time / tau
    raise ValueError(f"unknown time unit '{unit}'")


def read_dataset(ds):
    """A dataset's values: string datasets as an array of str, others as stored."""
    if ds.dtype.kind in "SO":
        return np.array([text(v) for v in ds[()]])
    return np.asarray(ds[()])


def read_group(group):
    """{name: values} of every dataset directly in an HDF5 group."""
    return {k: read_dataset(ds) for k, ds in group.items()}


def read_parameters(path):
    """The /parameters attributes of a granflow file (every program and table writes them)."""
    with h5py.File(path, "r") as f:
        return read_attrs(f["/parameters"])


def read_frame(path, frame=-1):
    """Positions, velocities, time (and its unit), radii, fixed flags, box edges and parameters
    of one stored frame, as a dict (granflow.Trajectory reads it, without its contacts)."""
    from granflow.trajectory import Trajectory  # here: granflow.trajectory imports this module

    with Trajectory(path) as run:
        f = run.frame(frame, contacts=False)
    return {
        "position": f.position,
        "velocity": f.velocity,
        "time": f.time,
        "time_unit": run.time_unit,
        "radius": run.radius,
        "fixed": run.fixed,
        "edges": f.box.edges,
        "parameters": run.parameters,
    }


def sha256(path):
    """Hex SHA-256 of a file."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()
