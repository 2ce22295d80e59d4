"""Units as granflow's files carry them (docs/file-format.md, Units): the H5MD units module's
grammar, the rule every table obeys, and the writer of a `unit` attribute.

A unit string is unit factors separated by single spaces: at most one number, first (an
integer or a decimal fraction with an optional signed integer power), then symbols of the
system "granflow reduced", each at most once, with an optional non-zero signed integer power
("L T-1"); "1" is a dimensionless number. The symbols: L (code length), M (code mass), T
(code time), tau (gf-incline's τ), rad and deg (plane angles).

A table obeys the rule when every numeric dataset has a `unit` attribute (a scalar,
fixed-length ASCII string) that is a unit string, or, in a long table whose rows hold
different quantities, a `unit_column` attribute naming a string dataset of its group that
gives each row's unit string (ROW_UNIT)."""
import re

import h5py
import numpy as np

SYSTEM = "granflow reduced"
SYMBOLS = ("L", "M", "T", "tau", "rad", "deg")
# The attribute of a dataset whose unit is given row by row, and the usual name of that column.
ROW_UNIT = "unit_column"
_NUMBER = re.compile(r"^[0-9]+(\.[0-9]+)?([+-][0-9]+)?$")
_FACTOR = re.compile(r"^([A-Za-z]+)([+-][1-9][0-9]*)?$")


def problem(unit):
    """Why `unit` is not a unit string of the system, or None if it is one."""
    if not isinstance(unit, str):
        return f"unit {unit!r} is not a string"
    if unit == "":
        return "empty unit"
    seen = set()
    for k, factor in enumerate(unit.split(" ")):
        if _NUMBER.match(factor):
            if k != 0:
                return f"number '{factor}' not first in '{unit}'"
            continue
        m = _FACTOR.match(factor)
        if not m:
            return f"'{factor}' in '{unit}' is neither a number nor a symbol with a signed power"
        if m.group(1) not in SYMBOLS:
            return f"unknown symbol '{m.group(1)}' in '{unit}'"
        if m.group(1) in seen:
            return f"symbol '{m.group(1)}' twice in '{unit}'"
        seen.add(m.group(1))
    return None


def times_power(unit, symbol, power):
    """The unit string of a quantity in `unit` multiplied by `symbol`^`power`: "T-1" times
    T+1 is "1", "L" times T-1 is "L T-1" (factors keep their order; a new one goes last)."""
    if problem(unit):
        raise ValueError(problem(unit))
    factors = [] if unit == "1" else unit.split(" ")
    number = factors.pop(0) if factors and _NUMBER.match(factors[0]) else None
    powers = {}
    for factor in factors:
        m = _FACTOR.match(factor)
        powers[m.group(1)] = int(m.group(2) or 1)
    powers[symbol] = powers.get(symbol, 0) + power
    out = ([number] if number else []) + [s if p == 1 else f"{s}{p:+d}" for s, p in powers.items() if p != 0]
    return " ".join(out) if out else "1"


def _text(value):
    return value.decode() if isinstance(value, bytes) else value


def attribute_problem(dataset):
    """Why a numeric dataset's `unit` attribute does not follow the rule, or None."""
    if "unit" not in dataset.attrs:
        return "no unit attribute"
    kind = dataset.attrs.get_id("unit").get_type()
    found = [problem(_text(dataset.attrs["unit"]))]
    if not isinstance(kind, h5py.h5t.TypeStringID) or kind.is_variable_str() or kind.get_cset() != h5py.h5t.CSET_ASCII:
        found.append("unit is not a fixed-length ASCII string")
    return "; ".join(w for w in found if w) or None


def table_problems(f):
    """Every breach of the rule in an open HDF5 file, as '/dataset: problem' strings."""
    found = []

    def visit(name, obj):
        if not isinstance(obj, h5py.Dataset) or obj.dtype.kind in "SOU":
            return
        if ROW_UNIT in obj.attrs and "unit" not in obj.attrs:
            column = obj.parent.get(_text(obj.attrs[ROW_UNIT]))
            if not isinstance(column, h5py.Dataset) or column.dtype.kind not in "SO" or column.shape != obj.shape[:1]:
                found.append(f"/{name}: {ROW_UNIT} names no string dataset of one unit per row")
                return
            for unit in sorted({_text(u) for u in column[()]}):
                if problem(unit):
                    found.append(f"/{name}: row unit: {problem(unit)}")
            return
        why = attribute_problem(obj)
        if why:
            found.append(f"/{name}: {why}")

    f.visititems(visit)
    return found


def write(dataset, unit):
    """Give a dataset its `unit` attribute as the H5MD units module asks (a scalar,
    fixed-length ASCII string); ValueError if `unit` is not a unit string."""
    why = problem(unit)
    if why:
        raise ValueError(f"{dataset.name}: {why}")
    dataset.attrs.create("unit", np.bytes_(unit.encode("ascii")))
