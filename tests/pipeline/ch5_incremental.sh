#!/usr/bin/env bash
# Pipeline test, chapter 5: the tiny sweep (SIZE=test) of `make ch5` end to end in a scratch
# copy of the tree (packings, shear runs, cluster windows, gf-correlate, figures 5.1-5.10),
# then the incremental rule: a change to gf-correlate's code makes `ch5-files` out of date,
# and remaking it redoes the correlation analyses and the figures but no simulation.
set -euo pipefail
src=${1:?usage: ch5_incremental.sh SOURCE_DIR}
source "$(dirname "${BASH_SOURCE[0]}")/lib/scratch_copy.bash"
scratch_copy "$src"

# The build dominates this test: only the three programs, and without optimisation (-O0
# compiles ~30 % faster; the tiny sweep does not need speed, and the stamps hash whatever
# machine code there is). Configuring first makes Makefile.sweeps keep this cache.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O0 -DNDEBUG" >/dev/null
M=(make --no-print-directory -f Makefile.sweeps SIZE=test "BUILD_TARGETS=gf-pack gf-shear gf-correlate"
   "PROGRAMS=gf-pack gf-shear gf-correlate")
fail() { echo "FAIL: $*" >&2; exit 1; }
up_to_date() { "${M[@]}" -q ch5-files; }
mtimes() { stat -c '%n %Y' "$@"; }

"${M[@]}" ch5 >/dev/null
for k in 1 2 3 4 5 6 7 8 9 10; do [ -s "figures/fig5_$k.png" ] || fail "figures/fig5_$k.png was not made"; done
tables=(runs/test/ch5_correlate.h5 runs/test/ch5_clusters.h5)
for t in "${tables[@]}"; do [ -s "$t" ] || fail "$t was not made"; done
mapfile -t trajectories < <(ls runs/test/shear_*.h5 runs/test/window_*.h5 runs/test/pack_*.h5)
[ "${#trajectories[@]}" -ge 8 ] || fail "expected the shear runs, windows and packings, got ${trajectories[*]}"
up_to_date || fail "fresh ch5 is not up to date"
# Runs at the ν of SHEAR_LONG_NU (0.5 in test.mk) take SHEAR_LONG_STRAIN, the others
# SHEAR_STRAIN; gf-correlate was asked to find each run's transient.
PYTHONPATH=python:pipelines /usr/bin/python3 - <<'PY' || fail "run lengths or transient detection not as test.mk asks"
import glob, h5py
for path in glob.glob("runs/test/shear_nu*.h5"):
    with h5py.File(path, "r") as f:
        strain = float(f["/parameters"].attrs["strain"])
    expected = 0.3 if "shear_nu0.500_" in path else 0.2
    assert abs(strain - expected) < 1e-12, (path, strain)
# gf-correlate (C++) and steady_state.py (Python) apply the same rule: each run's first frame
# averaged is the first frame at or after the strain steady_state.py starts that run at.
from analysis import steady_state as ss
with h5py.File("runs/test/ch5_correlate.h5", "r") as f:
    assert int(f["/correlation"].attrs["detect_transient"]) == 1
    inputs = [p.decode() if isinstance(p, bytes) else p for p in f["/runs/input"][...]]
    first = f["/runs/first_strain"][...]
for path, strain in zip(inputs, first):
    start = ss.steady_start(ss.read_run(path), 0.05)
    with h5py.File(path, "r") as f:
        every = int(f["/parameters"].attrs["frame-every"]) * float(f["/parameters"].attrs["strain-step"])
    assert start - 1e-9 <= strain < start + every + 1e-9, (path, start, strain)
PY
[ -z "$(find runs figures -name '*part*')" ] || fail "partial files left behind"
sims_before=$(mtimes "${trajectories[@]}")
tables_before=$(mtimes "${tables[@]}")
figures_before=$(mtimes figures/fig5_*.png)
sleep 1.1  # make compares seconds on some file systems

# A change to gf-correlate's code (a message string): the analyses are out of date ...
grep -q 'P(f) %s (%.0f%%)' tools/gf-correlate.cpp || fail "the message to edit is gone from tools/gf-correlate.cpp"
sed -i 's/P(f) %s (%.0f%%)/P(f) %s (confidence %.0f%%)/' tools/gf-correlate.cpp
"${M[@]}" build >/dev/null
if up_to_date; then fail "changing gf-correlate did not make ch5-files out of date"; fi
# ... and remaking them runs gf-correlate and the plots, never gf-shear or gf-pack.
plan=$("${M[@]}" -n ch5-files)
grep -q 'gf-correlate' <<<"$plan" || fail "gf-correlate would not be re-run"
if grep -qE 'bin/gf-(shear|pack)' <<<"$plan"; then fail "a simulation would be re-run: $plan"; fi
"${M[@]}" ch5 >/dev/null
up_to_date || fail "ch5-files not up to date after remaking them"
[ "$(mtimes "${trajectories[@]}")" = "$sims_before" ] || fail "simulations were redone"
tables_after=$(mtimes "${tables[@]}")
while read -r name before; do
  grep -q "^$name $before\$" <<<"$tables_after" && fail "$name was not remade"
done <<<"$tables_before"
while read -r name before; do
  [ "$(stat -c %Y "$name")" != "$before" ] || fail "$name was not remade"
done <<<"$figures_before"
echo "pipeline ch5_incremental: 1 passed, 0 failed"
