#!/usr/bin/env bash
# Pipeline test, chapter 6 and the whole reproduction: the tiny sweep (SIZE=test) of every
# chapter end to end in a scratch copy of the tree (quick-files: packings, shear runs, the elastic
# equilibrium runs with their warm-ups, the half-step run, the incline, every table, every figure,
# REPORT.md), after which `make -q` finds nothing to redo; then a new gf-kinetic stamp (what a
# change of gf-kinetic's machine code writes) makes exactly the kinetic table, its figures and the
# report out of date, a new gf-network stamp exactly the two force-network tables, Figs
# 6.5-6.8 and the report, and a new gf-stz stamp exactly the four D²min maps, their table, the
# STZ fit, Figs 6.9-6.11 and the report: remaking runs that program, its scripts and the report,
# never a simulation or another analysis, and leaves every other file as it was.
set -euo pipefail
src=${1:?usage: ch6_incremental.sh SOURCE_DIR}
for program in gf-kinetic gf-network gf-stz; do
  if [ ! -f "$src/tools/$program.cpp" ]; then
    echo "SKIP: $src/tools/$program.cpp does not exist (the chapter-6 tables need $program)"
    exit 77
  fi
done
source "$(dirname "${BASH_SOURCE[0]}")/lib/scratch_copy.bash"
scratch_copy "$src"

# The build dominates this test: only the programs, without optimisation (see ch5_incremental.sh).
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O0 -DNDEBUG" >/dev/null
programs="gf-pack gf-shear gf-correlate gf-incline gf-kinetic gf-network gf-stz"
M=(make --no-print-directory -f Makefile.sweeps SIZE=test "BUILD_TARGETS=$programs" "PROGRAMS=$programs")
fail() { echo "FAIL: $*" >&2; exit 1; }
up_to_date() { "${M[@]}" -q quick-files; }
mtimes() { stat -c '%n %Y' "$@"; }

"${M[@]}" build >/dev/null
"${M[@]}" quick-files >/dev/null
up_to_date || fail "a fresh full sweep is not up to date"
for f in figures/fig6_{1,3,5,6,7,8,9,10,11}.png runs/test/ch6_{kinetic,network,network_halfstep}.h5 \
         runs/test/ch6_{stz,incline,d2min_maps,d2min_a,d2min_b,d2min_c,d2min_d}.h5 figures/REPORT.md; do
  [ -s "$f" ] || fail "$f was not made"
done
# test.mk's e grid (0, 0.92) has no run of Fig 6.2's pair (0.5, 0.25): that figure is left out.
[ ! -e figures/fig6_2.png ] || fail "figures/fig6_2.png made without a run at e = 0.5 or 0.25"
grep -q '^## Chapter 6: kinetic' figures/REPORT.md || fail "REPORT.md has no chapter-6 kinetic section"
grep -q '^## Chapter 6: the force-network' figures/REPORT.md || fail "REPORT.md has no force-network section"
grep -q '^## Chapter 6: non-affine motion' figures/REPORT.md || fail "REPORT.md has no D²min section"
grep -q '^## Chapter 6: the STZ constitutive law' figures/REPORT.md || fail "REPORT.md has no STZ section"
for nu in 0.500 0.700; do
  for f in runs/test/eq{warm,settle,}_nu${nu}_s1.h5; do [ -s "$f" ] || fail "$f was not made"; done
done
# The equilibrium runs are elastic and unsheared, the measured run starts from the settling
# run's last frame, which starts from the warm-up's, and lasts CH6_EQ_STEPS; the table has one row per μ = 0 run of the ch4 grid and one
# equilibrium row per ν.
PYTHONPATH=python:pipelines /usr/bin/python3 - <<'PY' || fail "equilibrium runs or table not as test.mk asks"
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
# The half-step run: the ν = 0.7, e = 0 shear run at half the strain step, twice the steps and
# twice the steps between frames; the network tables: test.mk's grid (the ν = 0.7, e = 0 run),
# and the half-step run with its default-step run.
def attrs(path):
    with h5py.File(path, "r") as f:
        return {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f["/parameters"].attrs.items()}
half = attrs("runs/test/halfstep_nu0.700_e0.00_mu0.00_r1e-02_s1.h5")
full = attrs("runs/test/shear_nu0.700_e0.00_mu0.00_r1e-02_s1.h5")
assert float(half["strain-step"]) == float(full["strain-step"]) / 2, (half, full)
assert int(half["frame-every"]) == 2 * int(full["frame-every"]), (half, full)
assert int(half["total_steps"]) == 2 * int(full["total_steps"]), (half, full)
assert half["input"] == full["input"] and float(half["strain"]) == float(full["strain"]), (half, full)
def inputs(path):
    with h5py.File(path, "r") as f:
        return sorted(v.decode() if isinstance(v, bytes) else v for v in f["/runs/input"][...])
grid = inputs("runs/test/ch6_network.h5")
assert [v.split("/")[-1] for v in grid] == ["shear_nu0.700_e0.00_mu0.00_r1e-02_s1.h5"], grid
pair = inputs("runs/test/ch6_network_halfstep.h5")
assert [v.split("/")[-1] for v in pair] == ["halfstep_nu0.700_e0.00_mu0.00_r1e-02_s1.h5",
                                            "shear_nu0.700_e0.00_mu0.00_r1e-02_s1.h5"], pair
# Fig. 6.9: the branches start from the last frame of the ν = 0.7, e = 0 run, forward at +γ̇ to
# strain 0.15 and backward at −γ̇ to 0.05, a frame every 10 steps; the maps span the strains
# 0 → 0.05 and 0.10 → 0.15 (forward), 0 → 0.15 and 0 → −0.05, a, c, d from the parent's last
# frame (its index, resolved) to a frame of the branch.
stem = "nu0.700_e0.00_mu0.00_r1e-02_s1.h5"
for name, rate, strain in (("forward", 1e-2, 0.15), ("backward", -1e-2, 0.05)):
    b = attrs(f"runs/test/d2min_{name}_{stem}")
    assert b["input"].endswith("shear_" + stem) and int(b["frame"]) == -1, b
    assert float(b["rate"]) == rate and float(b["strain"]) == strain and int(b["frame-every"]) == 10, b
with h5py.File("runs/test/shear_" + stem, "r") as f:
    last = len(f["/particles/grains/position/step"]) - 1
for k, strain, source, reference in (("a", 0.05, "branch", last), ("b", 0.05, "trajectory", 10),
                                     ("c", 0.15, "branch", last), ("d", -0.05, "branch", last)):
    with h5py.File(f"runs/test/ch6_d2min_{k}.h5", "r") as f:
        a = {n: (v.decode() if isinstance(v, bytes) else v) for n, v in f["/d2min"].attrs.items()}
        assert abs(float(a["strain"]) - strain) < 1e-9, (k, a)
        assert a["current_source"] == source and int(a["reference_frame"]) == reference, (k, a)
with h5py.File("runs/test/ch6_d2min_maps.h5", "r") as f:
    assert list(f["/maps/start_strain"][...]) == [0, 0.1, 0, 0]
    assert f["/default/jaccard"].shape == (3,)
# The fit: the μ = 0 runs of test.mk's STZ grid (5 ν × 2 e) and the μ = 0.4 runs (4 ν, e = 0), a
# fit per μ, and the e = 0 incline rows of ch6_incline.h5.
with h5py.File("runs/test/ch6_stz.h5", "r") as f:
    kind = [v.decode() if isinstance(v, bytes) else v for v in f["/runs/kind"][...]]
    assert kind.count("shear") == 14, kind
    assert sorted(float(m) for m in f["/fit/friction"][...]) == [0.0, 0.4], f["/fit/friction"][...]
with h5py.File("runs/test/ch6_incline.h5", "r") as f:
    assert list(f["/runs/restitution"][...]) == [0.0, 0.0], f["/runs/restitution"][...]
PY
[ -z "$(find runs figures -name '*part*')" ] || fail "partial files left behind"

# Every output of the sweep with its time; a new stamp of $1 must remake exactly the files named
# after it, and its plan must name $1 and the scripts given, and no simulation or other analysis.
mapfile -t outputs < <(ls runs/test/*.h5 figures/*)
remakes() {
  local program=$1 scripts=$2 forbidden=$3
  shift 3
  local before plan name
  before=$(mtimes "${outputs[@]}")
  sleep 1.1  # make compares seconds on some file systems
  echo "a changed $program" > "build/stamps/$program.stamp"
  if up_to_date; then fail "a new $program stamp did not make quick-files out of date"; fi
  plan=$("${M[@]}" -n quick-files)
  grep -q "bin/$program" <<<"$plan" || fail "$program would not be re-run"
  for script in $scripts; do
    grep -q "$script" <<<"$plan" || fail "$script would not be run after a new $program stamp"
  done
  if grep -qE "$forbidden" <<<"$plan"; then fail "more than $program's outputs would be redone: $plan"; fi
  "${M[@]}" quick-files >/dev/null
  up_to_date || fail "quick-files not up to date after remaking $program's outputs"
  while read -r name time; do
    if printf '%s\n' "$@" | grep -qxF "$name"; then
      [ "$(stat -c %Y "$name")" != "$time" ] || fail "$name was not remade after a new $program stamp"
    else
      [ "$(stat -c %Y "$name")" = "$time" ] || fail "$name was remade after a new $program stamp"
    fi
  done <<<"$before"
}
simulations='bin/gf-(shear|pack|correlate|incline)|steady_state\.py|incline_bulk\.py|critical_angle\.py|plot/(ch[45]_|snapshot)'
remakes gf-kinetic "ch6_kinetic.py pipelines/report" "$simulations|bin/gf-(network|stz)|ch6_(network|stz)\.py|d2min_maps\.py" \
  runs/test/ch6_kinetic.h5 figures/fig6_1.png figures/fig6_3.png figures/REPORT.md
remakes gf-network "ch6_network.py pipelines/report" "$simulations|bin/gf-(kinetic|stz)|ch6_(kinetic|stz)\.py|d2min_maps\.py" \
  runs/test/ch6_network.h5 runs/test/ch6_network_halfstep.h5 figures/fig6_{5,6,7,8}.png figures/REPORT.md
remakes gf-stz "d2min_maps.py ch6_stz.py pipelines/report" "$simulations|bin/gf-(kinetic|network)|ch6_(kinetic|network)\.py" \
  runs/test/ch6_d2min_{a,b,c,d}.h5 runs/test/ch6_d2min_maps.h5 runs/test/ch6_stz.h5 figures/fig6_{9,10,11}.png \
  figures/REPORT.md
echo "pipeline ch6_incremental: 1 passed, 0 failed"
