"""Outputs written atomically (a temporary name beside the target, renamed into place only when
complete, like the C++ programs: make never sees a half-written file as up to date), and the
one writer of the analysis tables with their provenance."""
import contextlib
import os
import tempfile

import h5py
import numpy as np

from granflow import units
from granflow.hdf5 import read_attrs, read_group, sha256


def atomic_output(path):
    """A temporary path beside `path` (.name); commit() renames it into place, abandon() removes
    it if it is still there."""
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(
        dir=directory, prefix="." + os.path.basename(path) + ".part-", suffix=os.path.splitext(path)[1]
    )
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


def write_text(path, text):
    """Write `text` to `path` atomically (nothing at `path` until it is complete)."""
    out = atomic_output(path)
    try:
        with open(out.name, "w", newline="") as fh:
            fh.write(text)
        out.commit()
    finally:
        out.abandon()


def column(group, name, values, unit, meaning, dtype=float):
    """A dataset `name` of `group` holding `values` (as `dtype`), with its `unit` (a unit
    string, granflow.units) and `meaning` attributes."""
    dataset = group.create_dataset(name, data=np.asarray(values, dtype=dtype))
    units.write(dataset, unit)
    dataset.attrs["meaning"] = meaning
    return dataset


def column_group(parent, name, columns, column_units, integers=()):
    """Group `name` of `parent` with one dataset per column of `columns` ({column: values}): a
    column of strings as text, the columns named in `integers` as int64, the others as float.
    `column_units` gives each numeric column's unit string ({column: unit}, or one unit string
    for all); a unit that names a string column of the group (a long table's per-row units)
    gives the column that unit row by row (granflow.units.ROW_UNIT)."""
    group = parent.create_group(name)
    for column, values in columns.items():
        values = list(values)
        if values and isinstance(values[0], str):
            text_dataset(group, column, values)
            continue
        dataset = group.create_dataset(column, data=np.asarray(values, dtype=np.int64 if column in integers else float))
        unit = column_units if isinstance(column_units, str) else column_units[column]
        if unit in columns:
            dataset.attrs[units.ROW_UNIT] = unit
        else:
            units.write(dataset, unit)
    return group


def text_dataset(group, name, values):
    """A dataset of variable-length strings, one per row."""
    return group.create_dataset(name, data=np.array(list(values), dtype=object), dtype=h5py.string_dtype())


@contextlib.contextmanager
def table(output, script, command_line, parameters, inputs):
    """Write an analysis table atomically: yields the open h5py.File, already holding the
    provenance every table carries, so that a table says what made it from what:
    /parameters attributes program (the script's file name), script_sha256, command_line, then
    `parameters` (the script's settings, in order); /runs/input and /runs/input_sha256, one row
    per (path, sha256) of `inputs`. The file is renamed into place when the block completes and
    every numeric dataset has a valid unit (granflow.units: ValueError naming those without, and
    nothing written)."""
    out = atomic_output(output)
    try:
        with h5py.File(out.name, "w") as f:
            f.create_group("parameters").attrs.update(
                {
                    "program": os.path.basename(script),
                    "script_sha256": sha256(script),
                    "command_line": command_line,
                    **parameters,
                }
            )
            runs = f.create_group("runs")
            text_dataset(runs, "input", [path for path, _ in inputs])
            text_dataset(runs, "input_sha256", [digest for _, digest in inputs])
            yield f
            problems = units.table_problems(f)
        if problems:
            raise ValueError(f"{output}: datasets without a valid unit: " + "; ".join(problems))
        out.commit()
    finally:
        out.abandon()


def read_table(path, groups):
    """{group: {name: values}} for the given groups of a table (strings as text), plus
    "parameters": its /parameters attributes."""
    with h5py.File(path, "r") as f:
        result = {g: read_group(f[g]) for g in groups}
        result["parameters"] = read_attrs(f["parameters"])
    return result
