#!/usr/bin/env bash
# The programs at large N ("a million grains on one machine"): gf-pack, gf-shear with 1 and
# 2 threads, gf-correlate, gf-network, gf-kinetic and gf-stz d2min on one dense frictionless
# run per N. For each program: wall and CPU time, peak resident memory (/usr/bin/time -v),
# memory per grain, and for the trajectories the file size per stored frame. Writes
# OUT/million.tsv (one row per program, N and repetition) and OUT/million.md (the same as a
# Markdown table), and prints the latter. Figures and their reading: docs/performance.md,
# "A million grains".
#
#   bash bench/million.sh [N ...]            # default: 100000
#   TILE=10 WARM=100 STEPS=50 FRAMES=5 bash bench/million.sh 1000000   # the 10^6 column
#
# Environment (defaults in brackets):
#   BIN    the programs                                   [build/bin]
#   OUT    directory of the runs and the tables           [/tmp/granflow-million]
#   NU     packing fraction of the packing                [0.8]
#   WARM   steps of the warm-up run from the packing      [600]
#   WARM_STEP  its strain per step (gf-shear --strain-step) [1e-3]
#   STEPS  steps of each timed run (1 and 2 threads)      [100]
#   FRAMES stored frames of each timed run, besides step 0 [10]
#   TILE   K: instead of gf-pack at N, a packing of N/K² grains sheared to strain 2 and tiled
#          K x K (gf-pack --tile): the start for 10^6 grains, whose first steps from gf-pack's
#          packing solve a box-spanning cluster at a cost of about N^1.5 (5 min of CPU) [unset]
#   ONLY   space-separated subset of: pack warm shear1 shear2 correlate network kinetic d2min
#          (a later stage reuses the files an earlier run of the script left in OUT)
#
# The timed shear runs are branches from the last frame of the warm-up (gf-shear --frame -1)
# at gf-shear's default strain step 1e-3, after WARM steps from the packing's affine start
# (the first steps are the hardest). 600 steps (strain 0.6) are not yet the steady flow of
# bench/bench_engine (after strain 2), so the per-step cost measured here is an upper bound
# of the steady one; WARM=2000 at 10^5 measures how far above it is. At 10^6 the start from
# a packing costs minutes before the flow (see TILE). The timed runs' per-step cost is the stepping
# loop's wall time from gf-shear's summary line on stderr (reading the input and writing the
# last frame excluded, frame writing inside the loop included) divided by STEPS and N.
set -euo pipefail

BIN=${BIN:-build/bin}
OUT=${OUT:-/tmp/granflow-million}
NU=${NU:-0.8}
WARM=${WARM:-600}
WARM_STEP=${WARM_STEP:-1e-3}
STEPS=${STEPS:-100}
FRAMES=${FRAMES:-10}
ONLY=${ONLY:-pack warm shear1 shear2 correlate network kinetic d2min}
TILE=${TILE:-}
SIZES=("$@")
[ ${#SIZES[@]} -gt 0 ] || SIZES=(100000)
TIME=/usr/bin/time
[ -x "$TIME" ] || { echo "million.sh: needs GNU time at $TIME (apt install time)" >&2; exit 2; }
(( STEPS % FRAMES == 0 )) || { echo "million.sh: STEPS must be a multiple of FRAMES" >&2; exit 2; }
mkdir -p "$OUT"
TSV=$OUT/million.tsv
MD=$OUT/million.md
every=$((STEPS / FRAMES))

# Rows are appended (a repeated stage adds a row: repeats show the machine's spread); a
# fresh OUT starts a fresh table.
[ -f "$TSV" ] || printf 'program\tN\twall_s\tcpu_s\tpeak_rss_MiB\trss_B_per_grain\tengine_B_per_grain\tloop_s\tns_per_grain_step\tcpu_ns_per_grain_step\tsweeps_per_step\tfile_MB\tframes\tkB_per_frame\tB_per_grain_frame\tload\tcommand\n' >"$TSV"

load() { cut -d' ' -f1 /proc/loadavg; }
wants() { [[ " $ONLY " == *" $1 "* ]]; }

# run NAME N FILE FRAMES COMMAND...: runs the command under /usr/bin/time -v, appends a row.
# FILE (may be empty) is the trajectory whose size per frame is reported.
run() {
  local name=$1 n=$2 file=$3 frames=$4
  shift 4
  local log=$OUT/${name}_$n
  local before
  before=$(load)
  echo "million.sh: N=$n $name (load $before): $*" >&2
  if ! "$TIME" -v -o "$log.time" "$@" 2>"$log.err"; then
    echo "million.sh: $name failed at N=$n; its stderr:" >&2
    tail -5 "$log.err" >&2
    printf '%s\t%s\tFAILED\t\t\t\t\t\t\t\t\t\t\t\t\t%s\t%s\n' "$name" "$n" "$before" "$*" >>"$TSV"
    return 1
  fi
  local wall cpu rss
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ { n = split($2, t, ":"); s = 0;
          for (i = 1; i <= n; i++) s = s * 60 + t[i]; print s }' "$log.time")
  cpu=$(awk -F': ' '/User time/ { u = $2 } /System time/ { s = $2 } END { printf "%.2f", u + s }' "$log.time")
  rss=$(awk -F': ' '/Maximum resident set size/ { print $2 }' "$log.time")
  # gf-shear's summary: "gf-shear: S steps, T s, R steps/s, W sweeps/step[, engine E B/grain] -> F"
  local loop="" nsgs="" sweeps="" engine="" steps=""
  if grep -q ' steps/s, ' "$log.err"; then
    loop=$(sed -n 's/.* steps, \([0-9.]*\) s, .*/\1/p' "$log.err" | tail -1)
    sweeps=$(sed -n 's/.* \([0-9.]*\) sweeps\/step.*/\1/p' "$log.err" | tail -1)
    engine=$(sed -n 's/.*engine \([0-9]*\) B\/grain.*/\1/p' "$log.err" | tail -1)
    steps=$(sed -n 's/.*: \([0-9]*\) steps, .*/\1/p' "$log.err" | tail -1)
    local rate
    rate=$(sed -n 's/.* \([0-9.]*\) steps\/s, .*/\1/p' "$log.err" | tail -1)
    # The loop time has one decimal, the rate none: take whichever has more digits.
    nsgs=$(awk -v t="$loop" -v s="$steps" -v r="$rate" -v n="$n" \
      'BEGIN { printf "%.0f", (t * 10 >= r ? t / s : 1 / r) / n * 1e9 }')
  fi
  # The process's CPU time per grain-step: start-up and the last frame included, so an upper
  # bound, but far less inflated than the wall time when other work competes for the cores.
  local cpuns=""
  [ -z "$nsgs" ] || cpuns=$(awk -v c="$cpu" -v s="$steps" -v n="$n" 'BEGIN { printf "%.0f", c / s / n * 1e9 }')
  local size="" kbf="" bgf=""
  if [ -n "$file" ]; then
    local bytes
    bytes=$(stat -c %s "$file")
    size=$(awk -v b="$bytes" 'BEGIN { printf "%.1f", b / 1e6 }')
    kbf=$(awk -v b="$bytes" -v f="$frames" 'BEGIN { printf "%.0f", b / f / 1e3 }')
    bgf=$(awk -v b="$bytes" -v f="$frames" -v n="$n" 'BEGIN { printf "%.1f", b / f / n }')
  fi
  printf '%s\t%s\t%s\t%s\t%.0f\t%.0f\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s-%s\t%s\n' "$name" "$n" "$wall" "$cpu" \
    "$(awk -v r="$rss" 'BEGIN { print r / 1024 }')" "$(awk -v r="$rss" -v n="$n" 'BEGIN { print r * 1024 / n }')" \
    "$engine" "$loop" "$nsgs" "$cpuns" "$sweeps" "$size" "${file:+$frames}" "$kbf" "$bgf" "$before" "$(load)" "$*" >>"$TSV"
}

for n in "${SIZES[@]}"; do
  d=$OUT/n$n
  mkdir -p "$d"
  pack=$d/pack.h5 warm=$d/warm.h5 run1=$d/run_t1.h5 run2=$d/run_t2.h5
  if wants pack && [ -n "$TILE" ]; then
    # N/TILE² grains packed and sheared to strain 2, the last frame tiled TILE x TILE into
    # the packing of N grains (gf-pack --tile).
    small=$((n / (TILE * TILE)))
    (( small * TILE * TILE == n )) || { echo "million.sh: N=$n is not TILE²=$((TILE * TILE)) times a whole number" >&2; exit 2; }
    rm -f "$d/tile_pack.h5" "$d/tile_run.h5" "$pack"
    run gf-pack "$small" "$d/tile_pack.h5" 1 "$BIN/gf-pack" -n "$small" --packing-fraction "$NU" -o "$d/tile_pack.h5" || continue
    run "gf-shear to strain 2" "$small" "$d/tile_run.h5" 2 "$BIN/gf-shear" -i "$d/tile_pack.h5" -o "$d/tile_run.h5" \
      --strain 2 --frame-every 2000 --threads 1 || continue
    run "gf-pack --tile $TILE" "$n" "$pack" 1 "$BIN/gf-pack" -i "$d/tile_run.h5" --tile "$TILE" -o "$pack" || continue
  elif wants pack; then
    rm -f "$pack"
    run gf-pack "$n" "$pack" 1 "$BIN/gf-pack" -n "$n" --packing-fraction "$NU" -o "$pack" || continue
  fi
  if wants warm; then
    rm -f "$warm"
    run "gf-shear warm-up" "$n" "$warm" 2 "$BIN/gf-shear" -i "$pack" -o "$warm" --steps "$WARM" \
      --strain-step "$WARM_STEP" --frame-every "$WARM" --threads 1 || continue
  fi
  for t in 1 2; do
    if wants shear$t; then
      out=$d/run_t$t.h5
      rm -f "$out"
      run "gf-shear ${t}T" "$n" "$out" $((FRAMES + 1)) "$BIN/gf-shear" -i "$warm" --frame -1 -o "$out" \
        --steps "$STEPS" --frame-every "$every" --threads "$t" || continue 2
    fi
  done
  # The analyses read every stored frame of the 1-thread run (--from-strain 0: the run is short).
  if wants correlate; then
    rm -f "$d/correlate.h5"
    run gf-correlate "$n" "" 0 "$BIN/gf-correlate" --from-strain 0 -o "$d/correlate.h5" "$run1" || true
  fi
  if wants network; then
    rm -f "$d/network.h5"
    run gf-network "$n" "" 0 "$BIN/gf-network" --from-strain 0 -o "$d/network.h5" "$run1" || true
  fi
  if wants kinetic; then
    rm -f "$d/kinetic.h5"
    run gf-kinetic "$n" "" 0 "$BIN/gf-kinetic" --from-strain 0 -o "$d/kinetic.h5" "$run1" || true
  fi
  if wants d2min; then
    rm -f "$d/d2min.h5"
    run "gf-stz d2min" "$n" "" 0 "$BIN/gf-stz" d2min -i "$run1" --frames 0,-1 -o "$d/d2min.h5" || true
  fi
done

# The Markdown table: the columns a reader compares across N.
{
  echo "| program | N | wall s | CPU s | peak RSS MiB | RSS B/grain | engine B/grain | ns per grain-step (loop wall) | ns per grain-step (process CPU) | sweeps/step | file kB/frame | B/grain/frame | load before-after |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
  tail -n +2 "$TSV" | awk -F'\t' -v OFS=' | ' '{ print "| " $1, $2, $3, $4, $5, $6, $7, $9, $10, $11, $14, $15, $16 " |" }'
  echo
  echo "Commands:"
  echo
  tail -n +2 "$TSV" | awk -F'\t' '{ printf "- %s, N = %s: `%s`\n", $1, $2, $17 }'
} >"$MD"
cat "$MD"
