#!/usr/bin/env python3
"""test_install.py: the package granflow installs offline into a fresh venv and works there
without the repository (ctest python.test_install; docs/python.md).

1. Copies the package's sources (python/, lib/, CMakeLists.txt) to a temporary directory, so
   that pip's in-tree build writes nothing into the repository;
2. makes a venv with Debian's python3-venv (`python3 -m venv --system-site-packages`: numpy
   and h5py come from Debian) and runs in it, offline,
   `pip install --no-index --no-build-isolation --no-deps <copy>/python`;
3. makes a 64-grain packing, a short gf-shear run and gf-kinetic's table of it with the built
   programs (GRANFLOW_BIN, which ctest sets; <repo>/build/bin by default);
4. runs installed_check.py with the venv's Python in isolated mode (-I), from the temporary
   directory, with PYTHONPATH, PYTHONHOME and GRANFLOW_BUILD removed from its environment: it
   checks that granflow and its statistics library come from the venv, reads the run frame by
   frame against h5py, reads the table, and compares a blocking error with the one the
   repository's statistics library (the CMake build's) gives for the same series.

Exit 0 when every step passes, 1 when one fails (its output shown), 77 (skipped, said why)
when the venv module or the programs are missing."""
import os
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import programs  # noqa: E402  (a sibling module: the tests' inputs)

SKIP = 77


def step(what, command, env=None, cwd=None):
    start = time.monotonic()
    result = subprocess.run(command, env=env, cwd=cwd, capture_output=True, text=True)
    print(f"{what}: {time.monotonic() - start:.1f} s, exit {result.returncode}")
    if result.returncode != 0:
        print(f"$ {' '.join(command)}\n{result.stdout}{result.stderr}")
        print(f"test_install.py: FAILED at: {what}")
        sys.exit(1)
    return result


def copy_sources(destination):
    """The files `pip install ./python` reads: python/ (without build products), lib/ and
    CMakeLists.txt, as they lie in the repository."""
    ignore = shutil.ignore_patterns("build", "*.egg-info", "__pycache__", "*.pyc")
    shutil.copytree(os.path.join(programs.REPO, "python"), os.path.join(destination, "python"), ignore=ignore)
    shutil.copytree(os.path.join(programs.REPO, "lib"), os.path.join(destination, "lib"), ignore=ignore)
    shutil.copy(os.path.join(programs.REPO, "CMakeLists.txt"), destination)


def main():
    started = time.monotonic()
    needed = ("gf-pack", "gf-shear", "gf-kinetic")
    missing = [p for p in needed if not os.access(os.path.join(programs.BIN, p), os.X_OK)]
    if missing:
        print(f"test_install.py: skipped: {', '.join(missing)} not built in {programs.BIN} (GRANFLOW_BIN)")
        return SKIP
    with tempfile.TemporaryDirectory() as tmp:
        venv = os.path.join(tmp, "venv")
        command = [sys.executable, "-m", "venv", "--system-site-packages", venv]
        made = subprocess.run(command, capture_output=True, text=True)
        if made.returncode != 0:
            print(f"test_install.py: skipped: `{sys.executable} -m venv` failed (Debian's python3-venv missing?):")
            print(made.stdout + made.stderr)
            return SKIP
        print(f"venv: {time.monotonic() - started:.1f} s")
        source = os.path.join(tmp, "source")
        copy_sources(source)
        env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "GRANFLOW_BUILD")}
        python = os.path.join(venv, "bin", "python")
        step(
            "pip install",
            [python, "-m", "pip", "install", "--no-index", "--no-build-isolation", "--no-deps", "--no-cache-dir",
             os.path.join(source, "python")],
            env=env,
        )  # fmt: skip
        runs = os.path.join(tmp, "runs")
        os.mkdir(runs)
        os.symlink(programs.shear_run(runs), os.path.join(runs, "shear.h5"))
        programs.kinetic_table(runs, [os.path.join(runs, "shear.h5")])
        # A correlated series and its blocking error by the repository's statistics library (the
        # CMake build's): the venv's pip-built copy must give the same floats.
        import numpy as np

        sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
        from granflow import statistics

        rng = np.random.default_rng(46)
        series = np.empty(3000)
        series[0] = rng.normal()
        for i in range(1, len(series)):
            series[i] = 0.9 * series[i - 1] + rng.normal()
        np.save(os.path.join(runs, "series.npy"), series)
        expected = statistics.blocking_error(series)
        with open(os.path.join(runs, "series_blocking.txt"), "w") as fh:
            fh.write(f"{expected[0]!r} {expected[1]} {int(expected[2])}\n")
        check = os.path.join(tmp, "installed_check.py")
        shutil.copy(os.path.join(os.path.dirname(os.path.abspath(__file__)), "installed_check.py"), check)
        result = step("installed_check.py", [python, "-I", check, venv, runs], env=env, cwd=tmp)
        print(result.stdout, end="")
    print(f"test_install.py: passed in {time.monotonic() - started:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
