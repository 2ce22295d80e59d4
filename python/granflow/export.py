"""`python3 -m granflow export TRAJ.h5 -o OUT.gsd`: a trajectory's frames as a GSD file (HOOMD-blue's
format, read by OVITO, freud and MDAnalysis), each frame with its box, grains and contacts
(docs/python.md, "Export to GSD").

Per exported frame (a gsd.hoomd frame):
- configuration: step (the H5MD frame's step), dimensions 2, box [Lx, Ly, 1, xy, 0, 0] with the
  Lees–Edwards offset as the tilt, xy = δ/Ly: HOOMD's second lattice vector (xy·Ly, Ly) is
  granflow's image of the cell above, shifted by +δ in x. An incline (open in y) has xy = 0 and
  a box Ly widened to hold every grain (HOOMD boxes are periodic in every direction).
- particles: N, types ['free', 'fixed'] (typeid 1 for an immobile base grain), position
  (z = 0; translated by −(Lx/2, Ly/2), the box being centred on the origin in HOOMD, and
  wrapped by a multiple of Lx into the tilted box), diameter 2R, mass, velocity (lab frame),
  orientation (the quaternion of a rotation by θ about z), moment_inertia (0, 0, ½mR²) and
  angmom (HOOMD's angular-momentum quaternion P = 2 q ⊗ (0, 0, 0, Iω)).
- bonds: the frame's contacts (pair i < j), one bond type 'contact'.
- log: 'bonds/normal_force', 'bonds/tangential_force', 'bonds/binary_force' (one value per
  bond), 'particles/force_magnitude' (|Σ contact forces| per grain), 'particles/angular_velocity'
  (ω), and the scalars 'time', 'frame' (the index in the H5MD file), 'lees_edwards_offset' (δ).

Units are the H5MD file's (no conversion). gsd.hoomd stores the particles' and the box's arrays
as float32 (HOOMD's schema); the log arrays keep float64."""
import argparse
import os
import signal
import sys
import warnings

import numpy as np

from granflow.outputs import atomic_output
from granflow.trajectory import Trajectory

PROG = "granflow export"
TYPES = ["free", "fixed"]
BOND_TYPE = "contact"
BOND_LOGS = {  # log key: the Contacts attribute it holds
    "bonds/normal_force": "normal_force",
    "bonds/tangential_force": "tangential_force",
    "bonds/binary_force": "binary_force",
}


class Usage(Exception):
    """Bad usage or bad input: exit 2, one line."""


class Failure(Exception):
    """A failure on valid input (writing the output): exit 1, one line."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        raise Usage(message)


def parser():
    p = _Parser(
        prog="python3 -m granflow export",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        description=(
            "Write frames of a granflow trajectory (gf-pack, gf-shear, gf-incline) to a GSD file, HOOMD-blue's\n"
            "format, which OVITO, freud and MDAnalysis read: per frame the 2D box (the Lees-Edwards offset δ\n"
            "as the tilt xy = δ/Ly), the grains (positions translated by -(Lx/2, Ly/2) into HOOMD's centred\n"
            "box, diameters, masses, velocities, spins, type 'free' or 'fixed') and the contacts as bonds,\n"
            "with their normal, tangential and binary-collision forces as per-bond log arrays. Units are\n"
            "the trajectory's. See docs/python.md, \"Export to GSD\"."
        ),
        epilog=(
            "Exit status: 0 written; 2 bad usage or bad input (nothing written); 1 a failure while\n"
            "writing or an interruption (nothing written). The output is written under a temporary\n"
            "name beside it and renamed when complete."
        ),
    )
    p.add_argument("trajectory", metavar="TRAJ.h5", help="the trajectory to read (HDF5, H5MD layout)")
    p.add_argument(
        "-o", "--output", required=True, metavar="OUT.gsd",
        help="the GSD file to write (its directory must exist; an existing file is replaced)",
    )  # fmt: skip
    p.add_argument(
        "--frames", default=":", metavar="A:B[:S]",
        help="the frames to export, as a Python slice of the file's frames: A first (default 0), B past the "
        "last (default: the number of frames), S the step (default 1); negative A and B count from the end; "
        "a single K is frame K alone (a value starting with '-' needs the form --frames=-3:). A range out "
        "of the file's frames or selecting none is an error",
    )  # fmt: skip
    p.add_argument(
        "--no-contacts", action="store_true",
        help="export the grains only: no bonds and no force logs (the contacts are not read)",
    )  # fmt: skip
    p.add_argument(
        "--quiet", action="store_true",
        help="print nothing on success (by default a progress count while stderr is a terminal, and one "
        "summary line)",
    )  # fmt: skip
    return p


def parse_frames(text, frames, name="the trajectory"):
    """The frame indices `text` ("A:B[:S]" or "K") selects among `frames` frames of the file
    called `name` in messages; Usage if it is malformed, out of range or selects none."""
    where = f"option --frames: '{text}'"
    has = f"{name} has {frames} frame{'s' if frames != 1 else ''}, 0..{frames - 1}"
    parts = text.split(":")
    if len(parts) > 3:
        raise Usage(f"{where}: expected A:B[:S] or K")
    try:
        values = [int(p) if p.strip() else None for p in parts]
    except ValueError:
        raise Usage(f"{where}: expected integers, as A:B[:S] or K") from None
    if frames == 0:
        raise Usage(f"{name} has no frames")
    if len(values) == 1:
        if values[0] is None:
            raise Usage(f"{where}: expected A:B[:S] or K")
        k = values[0] + frames if values[0] < 0 else values[0]
        if not 0 <= k < frames:
            raise Usage(f"{where}: frame {values[0]} out of range ({has})")
        return [k]
    start, stop = values[0], values[1]
    step = values[2] if len(values) == 3 else None
    if step is not None and step < 1:
        raise Usage(f"{where}: the step must be at least 1")
    start = 0 if start is None else (start + frames if start < 0 else start)
    stop = frames if stop is None else (stop + frames if stop < 0 else stop)
    if not 0 <= start < frames or not 0 <= stop <= frames:
        raise Usage(f"{where}: out of range ({has})")
    selected = list(range(start, stop, step or 1))
    if not selected:
        raise Usage(f"{where}: selects no frame ({has})")
    return selected


def hoomd_box(frame):
    """(box [Lx, Ly, 1, xy, 0, 0], the shift to add to granflow's positions before the wrap) of a
    Frame: biperiodic cells keep Ly and tilt by xy = δ/Ly; an incline's open y is widened to hold
    every grain with its radius, untilted."""
    box = frame.box
    lx, ly = box.lx, box.ly
    if box.periodic[1]:
        return np.array([lx, ly, 1.0, box.offset / ly, 0.0, 0.0]), np.array([-lx / 2, -ly / 2])
    y, r = frame.position[:, 1], frame.radius
    low = min(0.0, float(np.min(y - r))) if len(y) else 0.0
    high = max(ly, float(np.max(y + r))) if len(y) else ly
    return np.array([lx, high - low, 1.0, 0.0, 0.0, 0.0]), np.array([-lx / 2, -(low + high) / 2])


def wrap(position, box):
    """position [N][2], already centred, moved by multiples of the lattice vectors into HOOMD's
    tilted box (fractional coordinates in [−½, ½)), as float32 [N][3] with z = 0. The wrap is
    checked again after the rounding to float32, which may land a grain on the upper face."""
    lx, ly, xy = float(box[0]), float(box[1]), float(box[3])
    p = np.array(position, dtype=np.float64)
    for _ in range(3):
        sy = np.floor(p[:, 1] / ly + 0.5)
        p[:, 0] -= sy * xy * ly
        p[:, 1] -= sy * ly
        sx = np.floor((p[:, 0] - xy * p[:, 1]) / lx + 0.5)
        p[:, 0] -= sx * lx
        out = np.zeros((len(p), 3), dtype=np.float32)
        out[:, :2] = p
        q = out[:, :2].astype(np.float64)
        fy = q[:, 1] / ly
        fx = (q[:, 0] - xy * q[:, 1]) / lx
        if np.all((fx >= -0.5) & (fx < 0.5) & (fy >= -0.5) & (fy < 0.5)):
            return out
        p = q
    return out


def grain_forces(contacts, grains):
    """[N]: |Σ of the contact forces| on each grain (F on pair[:, 0], −F on pair[:, 1])."""
    total = np.zeros((grains, 2))
    if len(contacts):
        force = contacts.force()
        np.add.at(total, contacts.pair[:, 0], force)
        np.add.at(total, contacts.pair[:, 1], -force)
    return np.hypot(total[:, 0], total[:, 1])


def gsd_frame(frame, make, contacts=True):
    """The gsd.hoomd frame (made by `make`, gsd.hoomd.Frame or Snapshot) of a granflow Frame."""
    box, shift = hoomd_box(frame)
    n = len(frame.position)
    g = make()
    g.configuration.step = frame.step
    g.configuration.dimensions = 2
    g.configuration.box = box
    p = g.particles
    p.N = n
    p.types = TYPES
    p.typeid = (np.asarray(frame.fixed) != 0).astype(np.uint32)
    p.position = wrap(frame.position + shift, box)
    p.diameter = (2 * frame.radius).astype(np.float32)
    p.mass = np.asarray(frame.mass, dtype=np.float32)
    velocity = np.zeros((n, 3), dtype=np.float32)
    velocity[:, :2] = frame.velocity
    p.velocity = velocity
    theta = np.zeros(n) if frame.orientation is None else np.asarray(frame.orientation, dtype=np.float64)
    omega = np.zeros(n) if frame.angular_velocity is None else np.asarray(frame.angular_velocity, dtype=np.float64)
    inertia = 0.5 * np.asarray(frame.mass, dtype=np.float64) * np.asarray(frame.radius, dtype=np.float64) ** 2
    c, s = np.cos(theta / 2), np.sin(theta / 2)
    p.orientation = np.column_stack((c, np.zeros(n), np.zeros(n), s)).astype(np.float32)
    p.moment_inertia = np.column_stack((np.zeros(n), np.zeros(n), inertia)).astype(np.float32)
    spin = inertia * omega  # L_z = Iω, the same in the body and the lab frame for a rotation about z
    p.angmom = np.column_stack((-2 * s * spin, np.zeros(n), np.zeros(n), 2 * c * spin)).astype(np.float32)
    g.log["particles/angular_velocity"] = omega
    g.log["time"] = np.array([frame.time], dtype=np.float64)
    g.log["frame"] = np.array([frame.index], dtype=np.int64)
    g.log["lees_edwards_offset"] = np.array([frame.box.offset], dtype=np.float64)
    b = g.bonds
    b.types = [BOND_TYPE]
    if contacts:
        pair = np.asarray(frame.contacts.pair, dtype=np.uint32).reshape(-1, 2)
        b.N = len(pair)
        b.typeid = np.zeros(len(pair), dtype=np.uint32)
        b.group = pair
        for key, name in BOND_LOGS.items():
            g.log[key] = np.asarray(getattr(frame.contacts, name), dtype=np.float64)
        g.log["particles/force_magnitude"] = grain_forces(frame.contacts, n)
    else:
        b.N = 0
        b.typeid = np.zeros(0, dtype=np.uint32)
        b.group = np.zeros((0, 2), dtype=np.uint32)
    return g


def _gsd():
    """gsd.hoomd, its frame class and its write mode (gsd 2: Snapshot and 'wb'; gsd 3: Frame and 'w')."""
    try:
        import gsd
        import gsd.hoomd
    except ImportError:
        raise Failure("the Python package gsd is not installed (Debian: python3-gsd; pip: gsd)") from None
    make = getattr(gsd.hoomd, "Frame", None) or gsd.hoomd.Snapshot
    major = int(str(getattr(gsd, "__version__", "2")).split(".")[0])
    return gsd.hoomd, make, "w" if major >= 3 else "wb"


def _terminate(signum, _frame):
    raise KeyboardInterrupt


def export(args):
    """Run the export of parsed `args`; returns the summary line. Raises Usage or Failure."""
    if not os.path.exists(args.trajectory):
        raise Usage(f"'{args.trajectory}': no such file")
    if not os.path.isfile(args.trajectory):
        raise Usage(f"'{args.trajectory}': not a regular file")
    directory = os.path.dirname(os.path.abspath(args.output))
    if not os.path.isdir(directory):
        raise Usage(f"'{args.output}': the directory '{os.path.dirname(args.output) or '.'}' does not exist")
    if os.path.isdir(args.output):
        raise Usage(f"'{args.output}': is a directory")
    try:
        run = Trajectory(args.trajectory)
    except (OSError, ValueError, KeyError) as e:
        raise Usage(f"'{args.trajectory}': cannot be read as a granflow trajectory ({_reason(e)})") from None
    with run:
        frames = parse_frames(args.frames, len(run), f"'{args.trajectory}'")
        hoomd, make, mode = _gsd()
        contacts = not args.no_contacts
        progress = sys.stderr.isatty() and not args.quiet
        try:
            out = atomic_output(args.output)
        except OSError as e:
            raise Failure(f"'{args.output}': cannot be written ({_reason(e)})") from None
        try:
            with warnings.catch_warnings():
                # gsd 2's comparison of bond arrays of different lengths with frame 0 warns in numpy.
                warnings.simplefilter("ignore", FutureWarning)
                with hoomd.open(out.name, mode) as f:
                    for count, k in enumerate(frames, 1):
                        try:
                            frame = run.frame(k, contacts=contacts)
                            g = gsd_frame(frame, make, contacts)
                        except (OSError, ValueError, KeyError, IndexError) as e:
                            raise Usage(f"'{args.trajectory}': frame {k}: {_reason(e)}") from None
                        try:
                            f.append(g)
                        except (OSError, RuntimeError) as e:
                            raise Failure(f"'{args.output}': cannot be written ({_reason(e)})") from None
                        if progress:
                            print(f"\r{PROG}: frame {count}/{len(frames)}", end="", file=sys.stderr, flush=True)
            if progress:
                print(file=sys.stderr)
            out.commit()
        except BaseException:
            if progress:
                print(file=sys.stderr)
            raise
        finally:
            out.abandon()
    what = f"frames {frames[0]}..{frames[-1]}" + ("" if contacts else ", no contacts")
    return f"{PROG}: wrote {len(frames)} frame(s) of '{args.trajectory}' ({what}) to '{args.output}'"


def _reason(e):
    text = str(e).strip() or type(e).__name__
    return " ".join(text.split())


def main(argv=None):
    """The command; returns the exit status."""
    old = signal.signal(signal.SIGTERM, _terminate)
    try:
        try:
            args = parser().parse_args(argv)
        except Usage as e:
            print(f"{PROG}: error: {e}", file=sys.stderr)
            return 2
        try:
            summary = export(args)
        except Usage as e:
            print(f"{PROG}: error: {e}", file=sys.stderr)
            return 2
        except Failure as e:
            print(f"{PROG}: failure: {e}", file=sys.stderr)
            return 1
        except KeyboardInterrupt:
            print(f"{PROG}: interrupted by signal; '{args.output}' not written", file=sys.stderr)
            return 1
        if not args.quiet:
            print(summary, file=sys.stderr)
        return 0
    finally:
        signal.signal(signal.SIGTERM, old)


if __name__ == "__main__":
    sys.exit(main())
