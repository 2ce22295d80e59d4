#!/usr/bin/env bash
# Pipeline test, chapter 6 and the whole reproduction: the tiny sweep (SIZE=test) of every
# chapter end to end in a scratch copy of the tree (quick-files: packings, shear runs, the elastic
# equilibrium runs with their warm-ups, the incline, every table, every figure, REPORT.md), after
# which `make -q` finds nothing to redo; then a new gf-kinetic stamp (what a change of gf-kinetic's
# machine code writes) makes exactly the chapter-6 table, its figures and the report out of date:
# remaking them runs gf-kinetic, the ch6 plots and report.py, never a simulation or another analysis.
set -euo pipefail
src=${1:?usage: ch6_incremental.sh SOURCE_DIR}
if [ ! -f "$src/tools/gf-kinetic.cpp" ]; then
  echo "SKIP: $src/tools/gf-kinetic.cpp does not exist (the chapter-6 table needs gf-kinetic)"
  exit 77
fi
source "$(dirname "${BASH_SOURCE[0]}")/lib/scratch_copy.bash"
scratch_copy "$src"

# The build dominates this test: only the programs, without optimisation (see ch5_incremental.sh).
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O0 -DNDEBUG" >/dev/null
programs="gf-pack gf-shear gf-correlate gf-incline gf-kinetic"
M=(make --no-print-directory -f Makefile.sweeps SIZE=test "BUILD_TARGETS=$programs" "PROGRAMS=$programs")
fail() { echo "FAIL: $*" >&2; exit 1; }
up_to_date() { "${M[@]}" -q quick-files; }
mtimes() { stat -c '%n %Y' "$@"; }

"${M[@]}" build >/dev/null
"${M[@]}" quick-files >/dev/null
up_to_date || fail "a fresh full sweep is not up to date"
for f in figures/fig6_1.png figures/fig6_3.png runs/test/ch6_kinetic.h5 figures/REPORT.md; do
  [ -s "$f" ] || fail "$f was not made"
done
# test.mk's e grid (0, 0.92) has no run of Fig 6.2's pair (0.5, 0.25): that figure is left out.
[ ! -e figures/fig6_2.png ] || fail "figures/fig6_2.png made without a run at e = 0.5 or 0.25"
grep -q '^## Chapter 6' figures/REPORT.md || fail "REPORT.md has no chapter-6 section"
for nu in 0.500 0.700; do
  for f in runs/test/eq{warm,settle,}_nu${nu}_s1.h5; do [ -s "$f" ] || fail "$f was not made"; done
done
# The equilibrium runs are elastic and unsheared, the measured run starts from the settling
# run's last frame, which starts from the warm-up's, and lasts CH6_EQ_STEPS; the table has one row per μ = 0 run of the ch4 grid and one
# equilibrium row per ν.
PYTHONPATH=pipelines /usr/bin/python3 - <<'PY' || fail "equilibrium runs or table not as test.mk asks"
import h5py
for nu in ("0.500", "0.700"):
    with h5py.File(f"runs/test/eq_nu{nu}_s1.h5", "r") as f:
        p = f["/parameters"].attrs
        assert float(p["rate"]) == 0 and float(p["restitution"]) == 1, dict(p)
        assert int(p["steps"]) == 100 and int(p["frame"]) == -1, dict(p)
        source = p["input"].decode() if isinstance(p["input"], bytes) else p["input"]
        assert source.endswith(f"eqsettle_nu{nu}_s1.h5"), source
    with h5py.File(f"runs/test/eqsettle_nu{nu}_s1.h5", "r") as f:
        source = f["/parameters"].attrs["input"]
        source = source.decode() if isinstance(source, bytes) else source
        assert source.endswith(f"eqwarm_nu{nu}_s1.h5"), source
with h5py.File("runs/test/ch6_kinetic.h5", "r") as f:
    inputs = sorted(v.decode() if isinstance(v, bytes) else v for v in f["/runs/input"][...])
    assert len(inputs) == 4 and all("_mu0.00_r1e-02_s1.h5" in v for v in inputs), inputs
    assert len(f["/equilibrium/packing_fraction"]) == 2
PY
[ -z "$(find runs figures -name '*part*')" ] || fail "partial files left behind"

mapfile -t runs < <(ls runs/test/*.h5 | grep -v -e ch6_kinetic.h5)
mapfile -t others < <(ls figures/*.png | grep -v fig6_)
ch6=(runs/test/ch6_kinetic.h5 figures/fig6_1.png figures/fig6_3.png figures/REPORT.md)
runs_before=$(mtimes "${runs[@]}")
others_before=$(mtimes "${others[@]}")
ch6_before=$(mtimes "${ch6[@]}")
sleep 1.1  # make compares seconds on some file systems

# A new gf-kinetic stamp: the ch6 outputs are out of date ...
echo "a changed gf-kinetic" > build/stamps/gf-kinetic.stamp
if up_to_date; then fail "a new gf-kinetic stamp did not make quick-files out of date"; fi
plan=$("${M[@]}" -n quick-files)
grep -q 'bin/gf-kinetic' <<<"$plan" || fail "gf-kinetic would not be re-run"
grep -q 'ch6_kinetic.py' <<<"$plan" || fail "the chapter-6 figures would not be redrawn"
grep -q 'report.py' <<<"$plan" || fail "the report would not be rewritten"
if grep -qE 'bin/gf-(shear|pack|correlate|incline)|steady_state\.py|incline_bulk\.py|critical_angle\.py|plot/(ch[45]_|snapshot)' \
  <<<"$plan"; then fail "more than chapter 6 would be redone: $plan"; fi
# ... and remaking redoes exactly them.
"${M[@]}" quick-files >/dev/null
up_to_date || fail "quick-files not up to date after remaking chapter 6"
[ "$(mtimes "${runs[@]}")" = "$runs_before" ] || fail "runs or other tables were redone"
[ "$(mtimes "${others[@]}")" = "$others_before" ] || fail "figures of other chapters were redrawn"
while read -r name before; do
  [ "$(stat -c %Y "$name")" != "$before" ] || fail "$name was not remade"
done <<<"$ch6_before"
echo "pipeline ch6_incremental: 1 passed, 0 failed"
