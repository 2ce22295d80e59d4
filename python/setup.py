"""Build of the Python package granflow (`pip install ./python`; docs/python.md).

The modules are granflow/*.py. Beside them, the package ships the shared library of
lib/statistics's C API (libgranflow_statistics.so, which granflow.statistics loads with
ctypes), compiled here from the repository's sources: the list of sources is read from
lib/CMakeLists.txt (target granflow_statistics), so that CMake and pip build the same library,
with the flags that matter for its floats (C++20, no contraction into FMA, as CMakeLists.txt
sets them). The package is built from a repository checkout (the sources are in ../lib), not
from an sdist. The version is CMakeLists.txt's project version."""
import os
import re

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
LIBRARY = "libgranflow_statistics.so"


def _read(path):
    try:
        with open(os.path.join(REPO, path), encoding="utf-8") as f:
            return f.read()
    except OSError as exc:
        raise SystemExit(f"setup.py: {exc}: granflow's Python package builds from a repository checkout") from None


def project_version():
    """The version of `project(granflow VERSION x.y.z ...)` in CMakeLists.txt."""
    m = re.search(r"^project\(granflow\s+VERSION\s+([0-9.]+)", _read("CMakeLists.txt"), re.M)
    if not m:
        raise SystemExit("setup.py: no `project(granflow VERSION ...)` in CMakeLists.txt")
    return m.group(1)


def statistics_sources():
    """The sources of `add_library(granflow_statistics SHARED ...)` in lib/CMakeLists.txt,
    relative to this directory (setuptools refuses absolute paths)."""
    m = re.search(r"add_library\(granflow_statistics\s+SHARED\s+([^)]*)\)", _read("lib/CMakeLists.txt"))
    if not m:
        raise SystemExit("setup.py: no `add_library(granflow_statistics SHARED ...)` in lib/CMakeLists.txt")
    sources = [os.path.join("..", "lib", s) for s in m.group(1).split()]
    missing = [s for s in sources if not os.path.isfile(os.path.join(HERE, s))]
    if missing:
        raise SystemExit(f"setup.py: {missing[0]} is missing")
    return sources


class BuildLibrary(build_ext):
    """build_ext that names the statistics library libgranflow_statistics.so (the name the
    CMake build gives it: a plain shared library for ctypes, not an extension module), and
    compiles its sources by absolute path, so that the objects stay under build_temp (with
    ../lib/... their paths would lead out of it)."""

    def get_ext_filename(self, fullname):
        # Called with the full name and with its last part alone (distutils' get_ext_fullpath).
        *package, name = fullname.split(".")
        return os.path.join(*package, LIBRARY) if name == "_statistics" else super().get_ext_filename(fullname)

    def build_extension(self, ext):
        relative = ext.sources  # restored: setuptools refuses absolute paths elsewhere
        ext.sources = [os.path.normpath(os.path.join(HERE, s)) for s in relative]
        try:
            super().build_extension(ext)
        finally:
            ext.sources = relative


statistics = Extension(
    "granflow._statistics",
    sources=statistics_sources(),
    include_dirs=[os.path.join(REPO, "lib")],
    language="c++",
    define_macros=[("NDEBUG", None)],
    # As CMakeLists.txt (Release): C++20, -O3, -ffp-contract=off (no a*b + c fused into an FMA,
    # so every rounding is the one written), symbols hidden but the C API's; no debug information
    # (Python's own flags ask for it).
    extra_compile_args=[
        "-std=c++20",
        "-O3",
        "-g0",
        "-ffp-contract=off",
        "-fvisibility=hidden",
        "-fvisibility-inlines-hidden",
    ],
)

setup(version=project_version(), packages=["granflow"], ext_modules=[statistics], cmdclass={"build_ext": BuildLibrary})
