"""Opens an XDMF file of gf-xdmf with ParaView's Xdmf Reader and compares what ParaView
reads with what h5py read from the trajectory (xdmf_expected.py):
pvpython check_xdmf.py RUN.xdmf2 EXPECTED.json. Exit 1 naming the first difference. A .xdmf2
file is opened as ParaView opens it by default (OpenDataFile), which must choose the Xdmf
Reader; any other name with the Xdmf Reader explicitly."""
import json
import math
import sys

from paraview import servermanager
from paraview.simple import OpenDataFile, XDMFReader

failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
    return condition


def close(a, b, tolerance=1e-12):
    return all(abs(x - y) <= tolerance * max(1.0, abs(y)) for x, y in zip(a, b)) and len(a) == len(b)


def blocks(data):
    named = {}
    for b in range(data.GetNumberOfBlocks()):
        named[data.GetMetaData(b).Get(data.NAME())] = data.GetBlock(b)
    return named


def arrays(fields):
    return sorted(fields.GetArrayName(i) for i in range(fields.GetNumberOfArrays()))


def values(array, components=1):
    return [array.GetComponent(t, c) for t in range(array.GetNumberOfTuples()) for c in range(components)]


def check_frame(reader, k, e):
    reader.UpdatePipeline(e["time"])
    data = servermanager.Fetch(reader)
    parts = blocks(data)
    want = ["box", "contacts", "grains"] if "ends" in e else ["box", "grains"]
    if not check(sorted(parts) == want, f"frame {k}: blocks {sorted(parts)}, expected {want}"):
        return
    grains, box = parts["grains"], parts["box"]
    n = e["grains"]
    check(grains.GetNumberOfPoints() == n, f"frame {k}: {grains.GetNumberOfPoints()} grain points, expected {n}")
    check(grains.GetNumberOfCells() == n, f"frame {k}: {grains.GetNumberOfCells()} grain cells, expected {n}")
    names = ["angular_velocity", "fixed", "mass", "orientation", "radius", "velocity"]
    check(arrays(grains.GetPointData()) == names, f"frame {k}: grain arrays {arrays(grains.GetPointData())}")
    points = [grains.GetPoint(p)[:2] for p in range(grains.GetNumberOfPoints())]
    check(
        close([c for p in points for c in p], [c for p in e["position"] for c in p]), f"frame {k}: grain centres differ"
    )
    pd = grains.GetPointData()
    check(close(values(pd.GetArray("radius")), e["radius"]), f"frame {k}: radius differs")
    velocity = pd.GetArray("velocity")
    check(
        close(values(velocity, 3), [c for v in e["velocity"] for c in (v[0], v[1], 0.0)]),
        f"frame {k}: velocity differs (components {velocity.GetNumberOfComponents()})",
    )
    check(close(values(pd.GetArray("angular_velocity")), e["angular_velocity"]), f"frame {k}: angular velocity differs")
    check(values(pd.GetArray("fixed")) == e["fixed"], f"frame {k}: fixed differs")

    corners = [box.GetPoint(p)[:2] for p in range(box.GetNumberOfPoints())]
    check(
        close([c for p in corners for c in p], [c for p in e["box"]["corners"] for c in p]),
        f"frame {k}: box corners {corners}, expected {e['box']['corners']}",
    )
    check(box.GetNumberOfCells() == 1, f"frame {k}: box has {box.GetNumberOfCells()} cells")
    check(close(values(box.GetCellData().GetArray("offset")), [e["box"]["offset"]]), f"frame {k}: box offset differs")

    if "ends" not in e:
        return
    contacts, c = parts["contacts"], e["contacts"]
    check(contacts.GetNumberOfCells() == c, f"frame {k}: {contacts.GetNumberOfCells()} contact cells, expected {c}")
    if c == 0:
        return
    names = ["age", "binary_force", "normal_force", "tangential_force"]
    check(arrays(contacts.GetCellData()) == names, f"frame {k}: contact arrays {arrays(contacts.GetCellData())}")
    ends = []
    for cell in range(contacts.GetNumberOfCells()):
        ids = contacts.GetCell(cell).GetPointIds()
        if not check(ids.GetNumberOfIds() == 2, f"frame {k}: contact {cell} has {ids.GetNumberOfIds()} points"):
            return
        ends += [contacts.GetPoint(ids.GetId(0))[:2], contacts.GetPoint(ids.GetId(1))[:2]]
    check(
        close([x for p in ends for x in p], [x for p in e["ends"] for x in p]),
        f"frame {k}: contact segments are not r_i to r_i - branch",
    )
    for name in ("normal_force", "tangential_force", "binary_force"):
        check(close(values(contacts.GetCellData().GetArray(name)), e[name]), f"frame {k}: {name} differs")
    longest = max(math.dist(ends[2 * s], ends[2 * s + 1]) for s in range(c))
    check(longest < 2 * max(e["radius"]), f"frame {k}: a contact segment is {longest:.3g} long")


def main():
    xdmf, expected = sys.argv[1], json.load(open(sys.argv[2]))
    if xdmf.endswith(".xdmf2"):
        reader = OpenDataFile(xdmf)
        if reader is None or reader.GetXMLName() != "XdmfReader":
            sys.exit(
                f"check_xdmf: ParaView opens {xdmf} with "
                f"{reader.GetXMLName() if reader else 'no reader'}, not the Xdmf Reader"
            )
    else:
        reader = XDMFReader(FileNames=[xdmf])
    reader.UpdatePipelineInformation()
    times = [float(t) for t in reader.TimestepValues]
    check(len(times) == expected["frames"], f"{len(times)} time steps, expected {expected['frames']}")
    frames = [k for k in expected if k != "frames"]
    for k in frames:
        check(close([times[int(k)]], [expected[k]["time"]]), f"frame {k}: time {times[int(k)]}")
        check_frame(reader, k, expected[k])
    for f in failures:
        print("check_xdmf: " + f, file=sys.stderr)
    if failures:
        sys.exit(1)
    print(
        "check_xdmf: frames "
        + ", ".join(
            f"{k} ({expected[k]['grains']} grains, {expected[k]['contacts']} contacts, {expected[k].get('wrapped', 0)} "
            f"across a boundary)"
            for k in frames
        )
        + " as in the trajectory"
    )


if __name__ == "__main__":
    main()
