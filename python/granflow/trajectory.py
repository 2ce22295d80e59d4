"""Reading a trajectory of gf-pack, gf-shear or gf-incline (HDF5 in the H5MD layout of
docs/file-format.md, "Trajectory files") lazily, one stored frame at a time, as NumPy arrays.

    with granflow.Trajectory("runs/quick/shear_nu0.800_e0.00_mu0.00_r1e-02_s1.h5") as run:
        for frame in run:
            frame.position, frame.velocity, frame.angular_velocity  # [N][2], [N][2], [N]
            frame.box.lx, frame.box.ly, frame.box.offset              # the Lees–Edwards cell
            frame.contacts.pair, frame.contacts.normal_force           # [C][2], [C]

The file stays open while the Trajectory is; each frame reads only its own rows. Lengths,
velocities and forces are in code units; times in the file's unit (Trajectory.time_unit:
"T", the code time, or "tau" for gf-incline; "code" in older files)."""
import h5py
import numpy as np

from granflow.hdf5 import read_attrs, text, time_unit

# The columns of /contacts (docs/file-format.md, Contacts) and their shapes per row, for the
# empty columns of a frame in a file without /contacts (a packing).
CONTACT_COLUMNS = {
    "pair": ((2,), np.int32),
    "normal_force": ((), np.float64),
    "tangential_force": ((), np.float64),
    "branch": ((2,), np.float64),
    "binary_force": ((), np.float64),
    "pre_normal_velocity": ((2,), np.float64),
    "age": ((), np.int64),
}


class Box:
    """The cell of one frame: periodic in x, and in y too (Lees–Edwards) unless `periodic[1]`
    is False (an incline, open at the top).

    Attributes: lx, ly (the cell's lengths), offset (δ, the Lees–Edwards image offset in
    [0, lx): the image of the cell above is shifted by +δ in x; 0 for an incline), edges (the
    stored [[lx, 0], [δ, ly]]), periodic ((True, True) or (True, False)), rate (γ̇ of
    /lees_edwards, None where the file has none)."""

    def __init__(self, edges, periodic, rate):
        self.edges = np.asarray(edges, dtype=np.float64)
        self.lx = float(self.edges[0, 0])
        self.ly = float(self.edges[1, 1])
        self.offset = float(self.edges[1, 0])
        self.periodic = periodic
        self.rate = rate

    @property
    def lengths(self):
        """np.array([lx, ly])."""
        return np.array([self.lx, self.ly])

    def __repr__(self):
        return f"Box(lx={self.lx!r}, ly={self.ly!r}, offset={self.offset!r}, periodic={self.periodic})"


class Contacts:
    """The contacts of one frame (pairs with a positive normal impulse), one row each, as
    docs/file-format.md's Contacts section defines them: `columns` holds every column the file
    has; the documented ones are also attributes.

    A contact pushes grain pair[:, 0] with normal_force·n̂ + tangential_force·t̂ and grain
    pair[:, 1] with the opposite, n̂ = branch/|branch|, t̂ = (−n̂_y, n̂_x) (force())."""

    def __init__(self, columns):
        self.columns = columns

    def __len__(self):
        return len(self.columns["pair"])

    def _column(self, name):
        try:
            return self.columns[name]
        except KeyError:
            raise KeyError(f"this trajectory's /contacts has no column '{name}'") from None

    @property
    def pair(self):
        """[C][2] int32: the grains (i, j), i < j, rows sorted by (i, j)."""
        return self._column("pair")

    @property
    def normal_force(self):
        """[C]: F_n ≥ 0 along n̂ (impulse / dt)."""
        return self._column("normal_force")

    @property
    def tangential_force(self):
        """[C]: F_t along t̂ = perp(n̂) (impulse / dt)."""
        return self._column("tangential_force")

    @property
    def branch(self):
        """[C][2]: b = r_i − r_j, the minimum image (Lees–Edwards)."""
        return self._column("branch")

    @property
    def binary_force(self):
        """[C]: the force of the same pair as an isolated binary collision (eq. 5.4)."""
        return self._column("binary_force")

    @property
    def pre_normal_velocity(self):
        """[C][2]: v_i·n̂ and v_j·n̂ before the step (fluctuating part)."""
        return self._column("pre_normal_velocity")

    @property
    def age(self):
        """[C] int64: consecutive steps with P_n > 0, this one included (1: a new contact)."""
        return self._column("age")

    def force(self):
        """[C][2]: the force on grain pair[:, 0], F_n n̂ + F_t t̂ (grain pair[:, 1] gets the opposite)."""
        b = np.asarray(self.branch, dtype=np.float64).reshape(-1, 2)
        n = b / np.linalg.norm(b, axis=1)[:, None]
        t = np.column_stack((-n[:, 1], n[:, 0]))
        return self.normal_force[:, None] * n + self.tangential_force[:, None] * t

    def __repr__(self):
        return f"Contacts({len(self)} rows: {', '.join(self.columns)})"


class Frame:
    """One stored frame of a trajectory.

    Attributes: index (the frame's index in the file), step, time (in the trajectory's
    time_unit), position [N][2] (centres; in [0, lx) × [0, ly) for a biperiodic cell),
    velocity [N][2] (lab frame, the mean shear flow included), orientation [N] (radians),
    angular_velocity [N] (ω, counter-clockwise positive), box (Box), contacts (Contacts, or
    None when read with contacts=False), and the grains' constants radius [N], mass [N],
    fixed [N] (uint8, 1 for an immobile base grain), shared with the Trajectory."""

    def __init__(self, **fields):
        self.__dict__.update(fields)

    def __repr__(self):
        contacts = "not read" if self.contacts is None else len(self.contacts)
        return (
            f"Frame(index={self.index}, step={self.step}, time={self.time!r}, grains={len(self.position)}, "
            f"contacts={contacts}, box={self.box!r})"
        )


class Trajectory:
    """A trajectory file opened for reading; a context manager (close() closes the file).

    len(t) is the number of stored frames; t[k] (negative k counts from the end) and
    t.frame(k, contacts=True) read frame k; iterating reads the frames in order, one at a
    time. Attributes read at opening: path, radius, mass, fixed (the grains' constants),
    parameters (the /parameters attributes, strings as text), time_unit ("T" or "tau";
    "code" in older files), periodic (the box's boundary, per axis), rate (γ̇ of
    /lees_edwards, None without it), has_contacts (whether the file has /contacts). steps
    and times: every frame's, read on use."""

    def __init__(self, path):
        self.path = path
        self._file = h5py.File(path, "r")
        try:
            self._open()
        except BaseException:
            self._file.close()
            raise

    def _open(self):
        f = self._file
        if "particles/grains/position/value" not in f:
            raise ValueError(f"{self.path}: no /particles/grains/position: not a granflow trajectory")
        grains = f["particles/grains"]
        self._grains = grains
        self.radius = grains["radius"][...]
        self.mass = grains["mass"][...] if "mass" in grains else np.pi * self.radius**2
        self.fixed = grains["fixed"][...] if "fixed" in grains else np.zeros(len(self.radius), dtype=np.uint8)
        self.parameters = read_attrs(f["parameters"]) if "parameters" in f else {}
        self.time_unit = time_unit(grains["position/time"])
        boundary = grains["box"].attrs.get("boundary", ("periodic", "periodic"))
        self.periodic = tuple(text(b) == "periodic" for b in boundary)
        self.rate = float(f["lees_edwards"].attrs["rate"]) if "lees_edwards" in f else None
        self.has_contacts = "contacts" in f
        self._frames = grains["position/value"].shape[0]
        if self.has_contacts:
            self._offsets = f["contacts/frame_offset"]
            if len(self._offsets) < self._frames + 1:
                raise ValueError(
                    f"{self.path}: /contacts/frame_offset has {len(self._offsets)} rows for {self._frames} frames "
                    f"(expected {self._frames + 1})"
                )
            self._contact_columns = {k: ds for k, ds in f["contacts"].items() if k != "frame_offset"}

    def close(self):
        """Close the file (frames already read stay valid)."""
        self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __len__(self):
        return self._frames

    def __getitem__(self, index):
        return self.frame(index)

    def __iter__(self):
        for k in range(self._frames):
            yield self.frame(k)

    @property
    def steps(self):
        """[n] int64: the step of every stored frame."""
        return self._grains["position/step"][...]

    @property
    def times(self):
        """[n]: the time of every stored frame, in time_unit."""
        return self._grains["position/time"][...]

    def _index(self, index):
        k = int(index)
        if k < 0:
            k += self._frames
        if not 0 <= k < self._frames:
            raise IndexError(f"{self.path}: frame {index} out of range ({self._frames} frames)")
        return k

    def contacts(self, index):
        """The Contacts of frame `index` (empty columns in a file without /contacts)."""
        k = self._index(index)
        if not self.has_contacts:
            return Contacts({name: np.zeros((0, *shape), dtype=t) for name, (shape, t) in CONTACT_COLUMNS.items()})
        first, last = (int(v) for v in self._offsets[k : k + 2])
        return Contacts({name: ds[first:last] for name, ds in self._contact_columns.items()})

    def frame(self, index, contacts=True):
        """Frame `index` (negative counts from the end), its contacts too unless contacts=False."""
        k = self._index(index)
        g = self._grains

        def element(name):
            return g[name + "/value"][k] if name in g else None

        return Frame(
            index=k,
            step=int(g["position/step"][k]),
            time=float(g["position/time"][k]),
            position=element("position"),
            velocity=element("velocity"),
            orientation=element("orientation"),
            angular_velocity=element("angular_velocity"),
            box=Box(g["box/edges/value"][k], self.periodic, self.rate),
            contacts=self.contacts(k) if contacts else None,
            radius=self.radius,
            mass=self.mass,
            fixed=self.fixed,
        )

    def __repr__(self):
        return f"Trajectory({self.path!r}, {self._frames} frames, {len(self.radius)} grains)"
