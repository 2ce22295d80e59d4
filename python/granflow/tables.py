"""Reading any analysis table of granflow as named arrays with their units and meanings: the
tables of gf-correlate, gf-kinetic, gf-network, gf-stz fit and gf-stz d2min, and those of the
pipelines' scripts (steady_state.py, incline_bulk.py, critical_angle.py, jamming_point.py, …);
their layouts are in docs/file-format.md, "Analysis tables".

    table = granflow.read_table("runs/quick/ch4_sweep.h5")
    nu = table["runs/packing_fraction"].values          # a NumPy array
    p = table["steady"]["pressure"]                      # a Column
    p.values, p.unit, p.meaning                          # array, "M T-2", "p = …"
    print(table.describe())                              # every dataset with its unit and meaning

A table is read whole when opened (tables are small: one row per run) and the file closed.
Strings (input paths, kinds) are arrays of str. `unit`, `units` and `meaning` are the
datasets' attributes of those names, None where a dataset has none: `unit` the H5MD unit
string ("M T-2", docs/file-format.md, Units; every numeric dataset has one, or, in a long
table, `unit_column` names the column of each row's unit), `units` the quantity in words
("force/length", the programs' tables only)."""
from collections.abc import Mapping

import h5py

from granflow.hdf5 import read_attrs, read_dataset


class Column:
    """One dataset of a table: name (its path in the file, e.g. "runs/packing_fraction"),
    values (a NumPy array; strings as str), unit, units and meaning (its attributes, None
    where absent) and attrs (all its attributes, strings as text). np.asarray(column) is its values."""

    def __init__(self, name, values, attrs):
        self.name = name
        self.values = values
        self.attrs = attrs
        self.units = attrs.get("units")
        self.unit = attrs.get("unit")
        self.meaning = attrs.get("meaning")

    @property
    def shape(self):
        """The values' shape."""
        return self.values.shape

    def __array__(self, dtype=None, copy=None):
        values = self.values if dtype is None else self.values.astype(dtype)
        return values.copy() if copy else values

    def __len__(self):
        return len(self.values)

    def __repr__(self):
        unit = f" [{self.unit}]" if self.unit else ""
        return f"Column({self.name!r}{unit}, shape={self.values.shape}, dtype={self.values.dtype})"


class Group(Mapping):
    """A group of a table: a mapping of its members' names to Column (a dataset) or Group (a
    subgroup), in the file's order. group["a/b"] reaches into subgroups. Attributes: name (the
    group's path, "" for the file), attrs (its attributes, strings as text)."""

    def __init__(self, name, attrs, members):
        self.name = name
        self.attrs = attrs
        self._members = members

    def __getitem__(self, key):
        head, _, rest = key.strip("/").partition("/")
        try:
            member = self._members[head]
        except KeyError:
            where = f"/{self.name}" if self.name else "the table"
            raise KeyError(f"{where} has no '{head}' (it has: {', '.join(self._members) or 'nothing'})") from None
        return member[rest] if rest else member

    def __iter__(self):
        return iter(self._members)

    def __len__(self):
        return len(self._members)

    def columns(self):
        """{name: Column} of the datasets directly in this group."""
        return {k: v for k, v in self._members.items() if isinstance(v, Column)}

    def groups(self):
        """{name: Group} of the subgroups directly in this group."""
        return {k: v for k, v in self._members.items() if isinstance(v, Group)}

    def arrays(self):
        """{name: values} of the datasets directly in this group (as granflow.hdf5.read_group)."""
        return {k: v.values for k, v in self.columns().items()}

    def walk(self):
        """Every Column of this group and its subgroups, depth first in the file's order."""
        for member in self._members.values():
            if isinstance(member, Group):
                yield from member.walk()
            else:
                yield member

    def describe(self):
        """A text listing of every dataset below this group, one a line: path, shape, [unit]
        and meaning (each where the dataset has them)."""
        lines = []
        for c in self.walk():
            unit = f" [{c.unit}]" if c.unit else ""
            meaning = f": {c.meaning}" if c.meaning else ""
            lines.append(f"{c.name} {c.values.shape}{unit}{meaning}")
        return "\n".join(lines)

    def __repr__(self):
        return f"Group({self.name!r}: {', '.join(self._members)})"


class Table(Group):
    """A whole table file (the root Group) with its provenance: path, parameters (the
    /parameters attributes), program ("gf-correlate", "gf-stz", "steady_state.py", …; None if
    unrecorded) and command (gf-stz's "fit" or "d2min", else None)."""

    def __init__(self, path, attrs, members):
        super().__init__("", attrs, members)
        self.path = path
        parameters = members.get("parameters")
        self.parameters = parameters.attrs if isinstance(parameters, Group) else {}
        self.program = self.parameters.get("program")
        self.command = self.parameters.get("command")

    @property
    def kind(self):
        """The program that wrote the table, with its command: "gf-stz fit", "gf-kinetic", …"""
        return " ".join(str(p) for p in (self.program, self.command) if p is not None) or None

    def __repr__(self):
        return f"Table({self.path!r}, {self.kind or 'unknown program'}: {', '.join(self)})"


def _group(obj, name):
    members = {}
    for key, item in obj.items():
        path = f"{name}/{key}" if name else key
        if isinstance(item, h5py.Group):
            members[key] = _group(item, path)
        elif isinstance(item, h5py.Dataset):
            members[key] = Column(path, read_dataset(item), read_attrs(item))
    return Group(name, read_attrs(obj), members)


def read_table(path):
    """The analysis table at `path`, whole, as a Table (see the module's docstring)."""
    with h5py.File(path, "r") as f:
        root = _group(f, "")
        return Table(path, root.attrs, dict(root.items()))
