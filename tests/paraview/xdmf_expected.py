"""What ParaView must show for frames of a trajectory, read from the .h5 with h5py (not
through the XDMF): python3 xdmf_expected.py RUN.h5 OUT.json FRAME...

Per frame: its time, the grains (count, centres, radius, velocity, angular velocity, fixed
flag), the contacts (count, segment ends r_i and r_i - branch, the three forces) and the
box corners with the Lees-Edwards offset. Used by tests/paraview/xdmf_paraview.sh."""
import json
import sys

import h5py
import numpy as np


def frame(f, k):
    g = "/particles/grains"
    pos = f[g + "/position/value"][k]
    out = {
        "time": float(f[g + "/position/time"][k]),
        "grains": int(pos.shape[0]),
        "position": pos.tolist(),
        "radius": f[g + "/radius"][:].tolist(),
        "velocity": f[g + "/velocity/value"][k].tolist(),
        "angular_velocity": f[g + "/angular_velocity/value"][k].tolist(),
        "fixed": f[g + "/fixed"][:].astype(int).tolist(),
    }
    lx, _, offset, ly = f[g + "/box/edges/value"][k].ravel()
    out["box"] = {"corners": [[0, 0], [lx, 0], [lx, ly], [0, ly]], "offset": float(offset)}
    if "/contacts" in f:
        first, last = f["/contacts/frame_offset"][k : k + 2]
        i = f["/contacts/pair"][first:last, 0]
        branch = f["/contacts/branch"][first:last]
        ends = np.empty((2 * len(i), 2))
        ends[0::2] = pos[i]
        ends[1::2] = pos[i] - branch
        out["contacts"] = int(last - first)
        out["ends"] = ends.tolist()
        for name in ("normal_force", "tangential_force", "binary_force"):
            out[name] = f["/contacts/" + name][first:last].tolist()
        # Contacts drawn from r_i to r_j would cross the box: those whose branch is not r_i - r_j.
        out["wrapped"] = int(
            np.sum(np.abs(pos[i] - pos[f["/contacts/pair"][first:last, 1]] - branch).max(axis=1) > 0.5 * min(lx, ly))
        )
    else:
        out["contacts"] = 0
    return out


def main():
    path, output, frames = sys.argv[1], sys.argv[2], [int(k) for k in sys.argv[3:]]
    with h5py.File(path, "r") as f:
        expected = {str(k): frame(f, k) for k in frames}
        expected["frames"] = int(f["/particles/grains/position/value"].shape[0])
    with open(output, "w") as out:
        json.dump(expected, out)


if __name__ == "__main__":
    main()
