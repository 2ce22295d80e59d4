"""units.EveryDataset: every dataset of every program's output has a valid H5MD `unit`.

Runs each built program on small inputs (python/tests/programs.py: 64-grain packings and
short gf-shear runs; a small incline), then the pipelines' steady_state.py, d2min_maps.py and
convergence.py on those outputs, and walks every HDF5 file they wrote with h5py. The rule is
granflow.units' (docs/file-format.md, Units), the one every table writer obeys: each numeric
dataset has a `unit` attribute, a scalar fixed-length ASCII string of unit factors separated
by single spaces (at most one number, first; symbols of the system, each once, with an
optional non-zero signed integer power: "L T-1"; "1" for a number), or, in a long table whose
rows hold different quantities, a `unit_column` attribute naming the string column of each
row's unit. String datasets (names, labels) have no unit. Every trajectory (a file with
/h5md) must declare the system in /h5md/modules/units (version [1, 0], system "granflow
reduced"), and its element times are in "T" (code time), or "tau" for gf-incline's. gf-xdmf
writes XML only: its HDF5 side is the trajectory, checked as such.

The checker then checks itself: on copies of one table and one trajectory with a unit
removed, a misspelt symbol, a repeated symbol and a missing declaration it must fail.

Usage: check_units.py BIN_DIR (ctest passes the build's bin/). Exit 0 on success."""
import os
import shutil
import subprocess
import sys
import tempfile

import h5py

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, "..", ".."))

from granflow import units  # noqa: E402  (python/, on PYTHONPATH: the rule, in one place)


def text(value):
    return value.decode() if isinstance(value, bytes) else value


def problems(path):
    """Every unit problem of one HDF5 file, as 'path: object: problem' lines."""
    with h5py.File(path, "r") as f:
        found = [f"{path}: {line}" for line in units.table_problems(f)]
        if "h5md" in f:
            module = f.get("h5md/modules/units")
            if not isinstance(module, h5py.Group):
                found.append(f"{path}: no /h5md/modules/units")
            else:
                if text(module.attrs.get("system")) != units.SYSTEM:
                    found.append(f"{path}: /h5md/modules/units system {module.attrs.get('system')!r}, not '{units.SYSTEM}'")
                if list(module.attrs.get("version", [])) != [1, 0]:
                    found.append(f"{path}: /h5md/modules/units version {module.attrs.get('version')!r}, not [1, 0]")
            program = text(f["parameters"].attrs.get("program", "")) if "parameters" in f else ""
            want = "tau" if program == "gf-incline" else "T"

            def time(name, obj):
                if isinstance(obj, h5py.Dataset) and name.endswith("/time") and "step" in obj.parent:
                    got = text(obj.attrs.get("unit"))
                    if got != want:
                        found.append(f"{path}: /{name}: time unit {got!r}, not '{want}' ({program})")

            f.visititems(time)
    return found


def outputs(directory):
    """Runs every program on small inputs in directory; returns {label: HDF5 file}."""
    sys.path.insert(0, os.path.join(REPO, "python", "tests"))
    import programs  # noqa: E402  (python/tests/programs.py, GRANFLOW_BIN)

    runs = [programs.shear_run(directory, nu, restitution=0.0) for nu in (0.70, 0.75, 0.80, 0.82)]
    files = {"gf-pack": os.path.join(directory, "pack_nu0.800.h5"), "gf-shear": runs[2]}
    files["gf-kinetic"] = programs.kinetic_table(directory, runs)
    files["gf-correlate"] = programs.correlate_table(directory, runs)
    out = os.path.join(directory, "correlate_reference.h5")
    programs.run("gf-correlate", "--from-strain", "0.1", "--reference", runs[0], "-o", out, runs[2], runs[3])
    files["gf-correlate --reference"] = out
    for label, args in (
        ("gf-network", ("gf-network", "--from-strain", "0.1", *runs[2:])),
        ("gf-stz fit", ("gf-stz fit", "--min-packing-fraction", "0.7", "--from-strain", "0.1", *runs)),
        ("gf-stz d2min", ("gf-stz d2min", "--frames", "5,10", "-i", runs[2])),
    ):
        files[label] = os.path.join(directory, label.replace(" ", "_") + ".h5")
        programs.run(*args, "-o", files[label])
    slope, incline = os.path.join(directory, "slope.h5"), os.path.join(directory, "incline.h5")
    programs.run("gf-pack", "--incline", "-n", str(programs.GRAINS), "-o", slope)
    programs.run("gf-incline", "-i", slope, "-o", incline, "--angle", "20", "--steps", "200")
    files["gf-pack --incline"], files["gf-incline"] = slope, incline
    programs.run("gf-xdmf", "-i", runs[2])  # XML beside the run; the run is checked above
    # The pipelines' tables (pipelines/analysis) from the same outputs.
    analysis = os.path.join(REPO, "pipelines", "analysis")

    def script(name, *args):
        label = name + ".py"
        files[label] = os.path.join(directory, name + ".h5")
        subprocess.run([sys.executable, os.path.join(analysis, label), *args, "-o", files[label]], check=True,
                       capture_output=True, text=True)

    script("steady_state", "--from-strain", "0.1", *runs)
    script("d2min_maps", files["gf-stz d2min"], files["gf-stz d2min"])
    # convergence.py reads per-run correlation tables (ξ_el is one number per table).
    single = os.path.join(directory, "correlate_single.h5")
    programs.run("gf-correlate", "--from-strain", "0.1", "--reference", runs[0], "-o", single, runs[2])
    script("convergence", "--default-step", "1e-3", "--reference", "0.7:0:0", files["steady_state.py"], single,
           files["gf-network"], files["gf-kinetic"])
    return files


def planted(directory, table, trajectory):
    """The checker's own check: each planted error must be reported."""
    failures = []

    def expect(label, source, change, needle):
        copy = os.path.join(directory, "planted_" + label.replace(" ", "_") + ".h5")
        shutil.copyfile(source, copy)
        with h5py.File(copy, "r+") as f:
            change(f)
        found = problems(copy)
        if not any(needle in line for line in found):
            failures.append(f"planted error not reported ({label}): {found}")
        else:
            print(f"planted ({label}): {found[0]}")

    def first_dataset(f):
        names = []
        f.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) and o.dtype.kind not in "SOU" else None)
        return f[names[0]]

    expect("unit removed", table, lambda f: first_dataset(f).attrs.__delitem__("unit"), "no unit attribute")
    expect("misspelt symbol", trajectory,
           lambda f: f["particles/grains/velocity/value"].attrs.__setitem__("unit", "L Tt-1"), "unknown symbol 'Tt'")
    expect("symbol twice", trajectory,
           lambda f: f["particles/grains/position/value"].attrs.__setitem__("unit", "L L"), "twice")
    expect("power without sign", table, lambda f: first_dataset(f).attrs.__setitem__("unit", "L2"), "neither")
    expect("no declaration", trajectory, lambda f: f.__delitem__("h5md/modules"), "no /h5md/modules/units")
    return failures


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    os.environ["GRANFLOW_BIN"] = os.path.abspath(sys.argv[1])
    with tempfile.TemporaryDirectory(prefix="granflow_units_") as directory:
        try:
            files = outputs(directory)
        except subprocess.CalledProcessError as e:
            sys.exit(f"{' '.join(e.cmd)} failed (exit {e.returncode}):\n{e.stderr}")
        found = []
        for label, path in files.items():
            lines = problems(path)
            with h5py.File(path, "r") as f:
                count = []
                f.visititems(lambda n, o: count.append(n) if isinstance(o, h5py.Dataset) else None)
            print(f"{label}: {len(count)} datasets, {len(lines)} problems")
            found += lines
        found += planted(directory, files["gf-kinetic"], files["gf-shear"])
        if found:
            print("\n".join(found), file=sys.stderr)
            sys.exit(1)
    print("every dataset has a valid unit")


if __name__ == "__main__":
    main()
