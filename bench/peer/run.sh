#!/usr/bin/env bash
# Peer comparison gf-shear vs LAMMPS (stiff soft spheres); see bench/peer/README.md.
#
#   bash bench/peer/run.sh                # build, time LAMMPS (once, cached) and gf-shear, print tables
#   bash bench/peer/run.sh convergence    # + the --strain-step × --tolerance study (slow at ν = 0.8)
#   bash bench/peer/run.sh mach           # LAMMPS at MACH_SERIES too, for the M → 0 extrapolation
#   bash bench/peer/run.sh table          # only print the tables from what is already in $OUT
#   bash bench/peer/run.sh friction       # μ = 0.4, ν = 0.78: LAMMPS with tangential history and gf-shear, timed
#   bash bench/peer/run.sh friction-table # only print the friction tables from $OUT/friction
#   bash bench/peer/run.sh rigid          # LAMMPS at RIGID_MACH beside the convergence study's runs (rigid limit)
#
# Environment (defaults in brackets):
#   OUT [build-peer/peer]   scratch directory for every generated file (never committed)
#   BUILD [build-peer]      CMake build directory (Release); SKIP_BUILD=1 uses it as it is
#   NUS ["0.6 0.8"]  GRAINS [2000]  SEED [1]  STRAIN [10]  RESTITUTION [0.5]
#   REPEAT [3]              gf-shear timing repetitions (a new set each call; older sets are kept)
#   LAMMPS_REPEAT [3]       LAMMPS repetitions; done once, RERUN_LAMMPS=1 redoes them
#   MACH [1e-3]  DT_FRACTION [0.02]   LAMMPS stiffness (Mach number) and dt / contact time
#   MACH_SERIES ["2e-3 5e-4"]         further Mach numbers of the 'mach' mode (run once, then reused)
#   CONV_STEPS ["4e-3 2e-3 1e-3 5e-4"]  CONV_TOLS ["1e-6 1e-8 1e-10"]  CONV_STRAIN [10]
#                           convergence grid (existing runs are reused; CONV_RERUN=1 redoes them)
#   CONV_EXTRA [""]         further grid directories (e.g. another build's OUT/conv) pooled into the fit
# Friction mode (files in $OUT/friction; every call adds a timing of each program):
#   FRICTION [0.4]  FRICTION_NUS [0.78]  GF_RESTITUTION [0]  LAMMPS_RESTITUTION [0.1]
#                           (a linear dashpot cannot give e = 0; tsuji damping reaches e ≥ 0.075)
#   GF_STRAIN [$STRAIN]  LAMMPS_STRAIN [$STRAIN]   strain of each run; the tables give the cost per
#                           strain unit and its extrapolation to $STRAIN
# Timings are one process on one core (OMP_NUM_THREADS=1); the machine's load at the time is
# recorded with each timing, since other work on the machine inflates wall times.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
OUT="$(mkdir -p "${OUT:-$ROOT/build-peer/peer}" && cd "${OUT:-$ROOT/build-peer/peer}" && pwd)"
BUILD="${BUILD:-$ROOT/build-peer}"
NUS="${NUS:-0.6 0.8}"
GRAINS="${GRAINS:-2000}"
SEED="${SEED:-1}"
STRAIN="${STRAIN:-10}"
RESTITUTION="${RESTITUTION:-0.5}"
REPEAT="${REPEAT:-3}"
LAMMPS_REPEAT="${LAMMPS_REPEAT:-3}"
MACH="${MACH:-1e-3}"
DT_FRACTION="${DT_FRACTION:-0.02}"
CONV_STEPS="${CONV_STEPS:-4e-3 2e-3 1e-3 5e-4}"
CONV_TOLS="${CONV_TOLS:-1e-6 1e-8 1e-10}"
CONV_STRAIN="${CONV_STRAIN:-10}"
MACH_SERIES="${MACH_SERIES:-2e-3 5e-4}"
FRICTION="${FRICTION:-0.4}"
FRICTION_NUS="${FRICTION_NUS:-0.78}"
GF_RESTITUTION="${GF_RESTITUTION:-0}"
LAMMPS_RESTITUTION="${LAMMPS_RESTITUTION:-0.1}"
GF_STRAIN="${GF_STRAIN:-$STRAIN}"
LAMMPS_STRAIN="${LAMMPS_STRAIN:-$STRAIN}"
FOUT="$OUT/friction"
PY=/usr/bin/python3
PEER="$PY $HERE/peer.py"
export OMP_NUM_THREADS=1
MODE="${1:-timing}"

log() { echo "[peer $(date +%H:%M:%S)] $*" >&2; }
load() { cut -d' ' -f1 /proc/loadavg; }

need() {
  command -v lmp >/dev/null || { echo "LAMMPS missing: apt-get install -y lammps" >&2; exit 2; }
  [ -x /usr/bin/time ] || { echo "/usr/bin/time missing: apt-get install -y time" >&2; exit 2; }
  $PY -c 'import h5py, numpy' 2>/dev/null || { echo "need python3-h5py python3-numpy" >&2; exit 2; }
}

build() {
  if [ "${SKIP_BUILD:-0}" != 1 ]; then
    log "building gf-pack gf-shear in $BUILD"
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >"$OUT/build.log" 2>&1
    cmake --build "$BUILD" -j2 --target gf-pack gf-shear >>"$OUT/build.log" 2>&1 ||
      { tail -20 "$OUT/build.log" >&2; exit 1; }
  fi
  GF_PACK="$BUILD/bin/gf-pack"
  GF_SHEAR="$BUILD/bin/gf-shear"
  VERSION="$("$GF_SHEAR" --version | awk '{print $NF}')"
  # identifies the engine build: hash of the gf-shear binary
  GF_HASH="$(sha256sum "$GF_SHEAR" | cut -c1-12)"
}

packing() {  # $1 = nu -> path
  local p="$OUT/pack_N${GRAINS}_nu$1_s$SEED.h5"
  [ -s "$p" ] || "$GF_PACK" -o "$p" --grains "$GRAINS" --packing-fraction "$1" --seed "$SEED" --quiet
  echo "$p"
}

# timings.tsv: tool nu repetition wall_s cpu_s load date binary-hash
timing_row() { printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$@" >>"$OUT/timings.tsv"; }

run_lammps() {
  local nu=$1 pack dir r
  pack=$(packing "$nu")
  dir="$OUT/lmp_nu$nu"
  $PEER deck "$pack" "$dir" --rate 1 --mach "$MACH" --restitution "$RESTITUTION" --strain "$STRAIN" \
    --dt-fraction "$DT_FRACTION" >/dev/null
  if [ "${RERUN_LAMMPS:-0}" = 1 ]; then
    [ -f "$OUT/timings.tsv" ] && { grep -v -P "^lammps\t$nu\t" "$OUT/timings.tsv" >"$OUT/timings.tmp" || true; mv "$OUT/timings.tmp" "$OUT/timings.tsv"; }
  elif [ -f "$OUT/timings.tsv" ] && grep -q -P "^lammps\t$nu\t" "$OUT/timings.tsv"; then
    log "LAMMPS ν=$nu: timings already recorded (RERUN_LAMMPS=1 to redo)"
    return
  fi
  for r in $(seq 1 "$LAMMPS_REPEAT"); do
    log "LAMMPS ν=$nu run $r/$LAMMPS_REPEAT"
    local l0; l0=$(load)
    (cd "$dir" && /usr/bin/time -f "%e %U %S" -o time.txt lmp -in in.shear -log log.lammps -nocite -screen none)
    read -r wall user sys <"$dir/time.txt"
    timing_row lammps "$nu" "$r" "$wall" "$(awk -v u="$user" -v s="$sys" 'BEGIN{print u+s}')" "$l0" "$(date -Is)" "lammps-$(lmp -h | sed -n 's/.*Simulator - \(.*\)$/\1/p' | tr ' ' '_')"
  done
}

run_gf() {
  local nu=$1 pack out r l0
  pack=$(packing "$nu")
  for r in $(seq 1 "$REPEAT"); do
    out="$OUT/gf_nu${nu}.h5"
    log "gf-shear ν=$nu run $r/$REPEAT"
    l0=$(load)
    rm -f "$out"
    /usr/bin/time -f "%e %U %S" -o "$OUT/gf_time.txt" \
      "$GF_SHEAR" -i "$pack" -o "$out" --strain "$STRAIN" --restitution "$RESTITUTION" --quiet
    # The process's wall time, as for LAMMPS: output files hold no timings (same command,
    # same bytes).
    read -r wall user sys <"$OUT/gf_time.txt"
    timing_row gf-shear "$nu" "$r" "$wall" "$(awk -v u="$user" -v s="$sys" 'BEGIN{print u+s}')" "$l0" "$(date -Is)" "$GF_HASH $VERSION"
  done
}

mach_series() {  # LAMMPS at further Mach numbers (physics only: the M → 0 extrapolation)
  local nu M dir
  for nu in $NUS; do
    for M in $MACH_SERIES; do
      dir="$OUT/lmp_nu${nu}_M$M"
      if [ -s "$dir/series.txt" ] && grep -q "^run " "$dir/in.shear" && [ -s "$dir/time.txt" ]; then continue; fi
      log "LAMMPS ν=$nu M=$M (physics only)"
      $PEER deck "$(packing "$nu")" "$dir" --rate 1 --mach "$M" --restitution "$RESTITUTION" --strain "$STRAIN" \
        --dt-fraction "$DT_FRACTION" >/dev/null
      (cd "$dir" && /usr/bin/time -f "%e %U %S" -o time.txt lmp -in in.shear -log log.lammps -nocite -screen none)
    done
  done
}

# friction/timings.tsv: tool nu strain wall_s cpu_s load date binary-hash
friction_row() { printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$@" >>"$FOUT/timings.tsv"; }

friction() {
  local nu pack dir out l0 wall user sys
  mkdir -p "$FOUT"
  for nu in $FRICTION_NUS; do
    pack=$(packing "$nu")
    dir="$FOUT/lmp_nu$nu"
    $PEER deck "$pack" "$dir" --rate 1 --mach "$MACH" --restitution "$LAMMPS_RESTITUTION" --strain "$LAMMPS_STRAIN" \
      --dt-fraction "$DT_FRACTION" --friction "$FRICTION" >/dev/null
    log "LAMMPS ν=$nu μ=$FRICTION e=$LAMMPS_RESTITUTION strain $LAMMPS_STRAIN"
    l0=$(load)
    (cd "$dir" && /usr/bin/time -f "%e %U %S" -o time.txt lmp -in in.shear -log log.lammps -nocite -screen none)
    read -r wall user sys <"$dir/time.txt"
    friction_row lammps "$nu" "$LAMMPS_STRAIN" "$wall" "$(awk -v u="$user" -v s="$sys" 'BEGIN{print u+s}')" "$l0" \
      "$(date -Is)" "lammps-$(lmp -h | sed -n 's/.*Simulator - \(.*\)$/\1/p' | tr ' ' '_')"
    out="$FOUT/gf_nu$nu.h5"
    log "gf-shear ν=$nu μ=$FRICTION e=$GF_RESTITUTION strain $GF_STRAIN"
    l0=$(load)
    rm -f "$out"
    /usr/bin/time -f "%e %U %S" -o "$FOUT/gf_time.txt" \
      "$GF_SHEAR" -i "$pack" -o "$out" --strain "$GF_STRAIN" --restitution "$GF_RESTITUTION" --friction "$FRICTION" --quiet
    read -r wall user sys <"$FOUT/gf_time.txt"
    friction_row gf-shear "$nu" "$GF_STRAIN" "$wall" "$(awk -v u="$user" -v s="$sys" 'BEGIN{print u+s}')" "$l0" \
      "$(date -Is)" "$GF_HASH $VERSION"
  done
}

friction_table() { $PEER friction-report "$FOUT" --nus "$FRICTION_NUS" --strain "$STRAIN"; }

convergence() {
  local nu ds tol pack out
  mkdir -p "$OUT/conv"
  for nu in $NUS; do
    pack=$(packing "$nu")
    for tol in $CONV_TOLS; do
      for ds in $CONV_STEPS; do
        out="$OUT/conv/nu${nu}_ds${ds}_tol${tol}.h5"
        if [ -s "$out" ] && [ "${CONV_RERUN:-0}" != 1 ]; then continue; fi
        log "convergence ν=$nu --strain-step $ds --tolerance $tol"
        /usr/bin/time -f "%e %U %S" -o "${out%.h5}.time" \
          "$GF_SHEAR" -i "$pack" -o "$out" --strain "$CONV_STRAIN" --restitution "$RESTITUTION" \
          --strain-step "$ds" --tolerance "$tol" --frame-every 1000000 --quiet
      done
    done
  done
}

table() {
  local extra=() d
  for d in ${CONV_EXTRA:-}; do extra+=(--extra-conv "$d"); done
  $PY "$HERE/peer.py" report "$OUT" --nus "$NUS" "${extra[@]}"
}

need
# The rigid limit (docs/results/convergence.md): LAMMPS at RIGID_MACH from the convergence study's
# packing (RIGID_PACKING, N = 1000, ν = 0.80), e = RESTITUTION, RIGID_STRAIN strain units, timed,
# beside the study's gf-shear runs of that point at every step (RIGID_RUNS), all through `peer.py
# stats` (ratio of means, blocks of one strain unit from strain 1). Needs the study's runs
# (make -f Makefile.sweeps convergence).
RIGID_PACKING="${RIGID_PACKING:-$ROOT/runs/convergence/pack_n1000_nu0.800_s1.h5}"
RIGID_RUNS="${RIGID_RUNS:-$ROOT/runs/convergence/conv_n1000_nu0.800_e0.50_mu0.00_dt*_tol1e-10_s1.h5}"
RIGID_MACH="${RIGID_MACH:-1.3e-3 4e-4 1.3e-4}"
RIGID_STRAIN="${RIGID_STRAIN:-20}"
rigid() {
  local M dir f
  [ -s "$RIGID_PACKING" ] || { echo "no $RIGID_PACKING: run make -f Makefile.sweeps convergence first" >&2; exit 2; }
  for M in $RIGID_MACH; do
    dir="$OUT/rigid/lmp_M$M"
    if [ ! -s "$dir/cpu.txt" ]; then
      log "LAMMPS M=$M, $RIGID_STRAIN strain units"
      $PEER deck "$RIGID_PACKING" "$dir" --rate 1 --mach "$M" --restitution "$RESTITUTION" --strain "$RIGID_STRAIN" \
        --dt-fraction "$DT_FRACTION" >/dev/null
      (cd "$dir" && /usr/bin/time -f "%U %S" -o time.txt lmp -in in.shear -log log.lammps -nocite -screen none)
      awk '{ print $1 + $2 }' "$dir/time.txt" >"$dir/cpu.txt"
    fi
  done
  printf '| model | setting | CPU s | p/γ̇² | s/p | T/γ̇² |\n|---|---|---|---|---|---|\n'
  for M in $RIGID_MACH; do
    dir="$OUT/rigid/lmp_M$M"
    $PEER stats "$dir/series.txt" | $PY -c "import json, sys; d = json.load(sys.stdin); print(f\"| LAMMPS | M = $M | $(cat "$dir/cpu.txt") | {d['p']:.2f} ± {d['p_err']:.2f} | {d['mu']:.4f} ± {d['mu_err']:.4f} | {d['T']:.3f} ± {d['T_err']:.3f} |\")"
  done
  for f in $RIGID_RUNS; do
    [ -s "$f" ] || continue
    echo "$f"
  done | while read -r f; do
    $PEER stats "$f" | $PY -c "import json, sys, h5py; d = json.load(sys.stdin); h = h5py.File('$f', 'r')['parameters'].attrs; print(f\"| gf-shear | γ̇dt = {float(h['dt']) * abs(float(h['rate'])):g} | — | {d['p']:.2f} ± {d['p_err']:.2f} | {d['mu']:.4f} ± {d['mu_err']:.4f} | {d['T']:.3f} ± {d['T_err']:.3f} |\")"
  done | sort -t'=' -k2 -g -r
}

case "$MODE" in
  table) table ;;
  timing | convergence | all)
    build
    for nu in $NUS; do run_lammps "$nu"; done
    for nu in $NUS; do run_gf "$nu"; done
    if [ "$MODE" != timing ]; then convergence; fi
    table
    ;;
  conv-only) build; convergence; table ;;
  mach) build; mach_series; table ;;
  friction) build; friction; friction_table ;;
  friction-table) friction_table ;;
  rigid) need; rigid ;;
  *) echo "usage: bash bench/peer/run.sh [timing|convergence|conv-only|mach|table|friction|friction-table|rigid]" >&2; exit 2 ;;
esac
