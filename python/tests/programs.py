"""Small inputs made by the built programs for the package's tests (GRANFLOW_BIN, which ctest
sets; <repo>/build/bin by default): packings and short gf-shear runs of 64 grains, and the
tables of gf-kinetic, gf-correlate, gf-network and gf-stz made from them. Each takes well
under a second."""
import os
import subprocess
import unittest

REPO = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
BIN = os.environ.get("GRANFLOW_BIN") or os.path.join(REPO, "build", "bin")
GRAINS = 64
STRAIN = 0.5  # 500 steps at the default strain step
FRAME_EVERY = 25  # 21 frames
FROM_STRAIN = 0.1


def require(*programs):
    """unittest.skip unless every program is built in BIN."""
    missing = [p for p in programs if not os.access(os.path.join(BIN, p), os.X_OK)]
    return unittest.skipIf(missing, f"{', '.join(missing)} not built in {BIN} (GRANFLOW_BIN; ctest sets it)")


def run(program, *args):
    """Run a built program (`program` may be "gf-stz fit": a program and its command) with
    --quiet; CalledProcessError with its stderr if it fails."""
    name, *command = program.split()
    full = [os.path.join(BIN, name), *command, *args, "--quiet"]
    result = subprocess.run(full, capture_output=True, text=True)
    if result.returncode != 0:
        raise subprocess.CalledProcessError(result.returncode, full, result.stdout, result.stderr)


def shear_run(directory, packing_fraction=0.8, restitution=0.5, rate=1.0):
    """A gf-pack packing of GRAINS grains at this ν and a gf-shear run from it (STRAIN, a frame
    every FRAME_EVERY steps); returns the run's path."""
    pack = os.path.join(directory, f"pack_nu{packing_fraction:.3f}.h5")
    out = os.path.join(directory, f"shear_nu{packing_fraction:.3f}_e{restitution:.2f}_r{rate:g}.h5")
    if not os.path.exists(pack):
        run("gf-pack", "-n", str(GRAINS), "--packing-fraction", str(packing_fraction), "-o", pack)
    run(
        "gf-shear",
        "-i",
        pack,
        "-o",
        out,
        "--rate",
        str(rate),
        "--restitution",
        str(restitution),
        "--strain",
        str(STRAIN),
        "--frame-every",
        str(FRAME_EVERY),
    )
    return out


def incline_run(directory):
    """A gf-pack incline start of GRAINS grains and a short gf-incline run from it at 20° (200
    steps, a frame every 50); returns (the start's path, the run's path)."""
    pack = os.path.join(directory, "incline_pack.h5")
    out = os.path.join(directory, "incline.h5")
    run("gf-pack", "--incline", "-n", str(GRAINS), "-o", pack)
    run(
        "gf-incline", "-i", pack, "-o", out, "--angle", "20", "--steps", "200",
        "--frame-every", "50", "--profile-block", "50", "--from-time", "0",
    )  # fmt: skip
    return pack, out


def kinetic_table(directory, runs):
    """gf-kinetic's table of the runs (from FROM_STRAIN); returns its path."""
    out = os.path.join(directory, "kinetic.h5")
    run("gf-kinetic", "--from-strain", str(FROM_STRAIN), "-o", out, *runs)
    return out


def correlate_table(directory, runs):
    """gf-correlate's table of the runs (from FROM_STRAIN); returns its path."""
    out = os.path.join(directory, "correlate.h5")
    run("gf-correlate", "--from-strain", str(FROM_STRAIN), "-o", out, *runs)
    return out
