"""`make` of a step study's target (convergence, phase-step, incline-step) from a test: a grid
file and placeholder program stamps written once in a scratch directory (a newer grid or stamp
would make every table out of date), the built programs of GRANFLOW_BIN, runs under d/runs."""
import os
import subprocess

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
HAVE_PROGRAMS = os.path.isfile(os.path.join(os.environ.get("GRANFLOW_BIN", "-"), "gf-shear"))
SKIP_REASON = "GRANFLOW_BIN (the built gf-* programs) not given; ctest sets it"


def run(d, grid_text, grid_variables, programs, goal, *extra):
    """make GOAL with the grid (written to d/grid.mk on the first call) given as each of
    grid_variables, stamps for `programs` (and the statistics library) in d/stamps, CONV_RUNS=d/runs
    and FIGURES=d/figures; returns the CompletedProcess."""
    grid = os.path.join(d, "grid.mk")
    if not os.path.exists(grid):
        with open(grid, "w") as fh:
            fh.write(grid_text)
    stamps = os.path.join(d, "stamps")
    if not os.path.exists(stamps):
        os.makedirs(stamps)
        for prog in (*programs, "libgranflow_statistics.so"):
            with open(os.path.join(stamps, prog + ".stamp"), "w") as fh:
                fh.write("0\n")
    cmd = [
        "make", "--no-print-directory", "-f", "Makefile.sweeps", f"BIN={os.environ['GRANFLOW_BIN']}",
        f"STAMPS={stamps}", *(f"{v}={grid}" for v in grid_variables), f"CONV_RUNS={d}/runs",
        "PYTHON=/usr/bin/python3", f"FIGURES={d}/figures", *extra, goal,
    ]
    return subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)


def assert_refused(test, res, d, needle):
    """A grid refused by make: exit 2, one line naming the problem, nothing made."""
    test.assertEqual(res.returncode, 2, res.stdout + res.stderr)
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    test.assertEqual(len(lines), 1, res.stderr)
    test.assertIn(needle, lines[0])
    test.assertFalse(os.path.exists(os.path.join(d, "runs")))
