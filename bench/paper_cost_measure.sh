#!/bin/bash
# The costs per grain-step that bench/paper_cost.py takes (docs/performance.md, "Paper size: cost
# per figure"): short gf-shear runs at N = 10^4, one at a time, CPU time of each process.
#
#   bash bench/paper_cost_measure.sh [BIN [DIR]]      (defaults build/bin, a temporary directory)
#
# Sheared (mu = 0, rate 1e-2, strain step 1e-3): a packing per nu (gf-pack, seed 1), a warm-up of
# W steps from it (the first steps from a packing are not the steady flow), then M steps from the
# warm-up's last frame, timed. Equilibrium gas (rate 0, e = 1, the chapter-6 recipe's steps for that
# nu): 500 steps at the warm-up step from the packing, then 2000 at the production step, timed.
# A one-step run from the same state gives the start-up, one step and the output; subtracted from
# the timed run, the rest is M - 1 steps.
# CASES: nu:e:W:M of the sheared runs. Prints one line per run and the tables in paper_cost.py's
# syntax; `uptime` before and after each run (a loaded machine measures slower).
set -euo pipefail
BIN=${1:-build/bin}
DIR=${2:-$(mktemp -d)}
N=10000
CASES=${CASES:-"0.100:0.00:5000:1000 0.300:0.00:5000:1000 0.500:0.00:3000:1000 0.650:0.00:2000:1000
0.700:0.00:2000:1000 0.760:0.00:1000:500 0.780:0.00:1000:500 0.800:0.00:1000:500 0.810:0.00:1000:300
0.820:0.00:1000:300 0.830:0.00:1000:300 0.300:0.92:3000:1000 0.700:0.92:2000:1000 0.760:0.92:1000:500
0.800:0.92:1000:500 0.820:0.92:1000:300 0.830:0.92:1000:300 0.800:0.50:1000:500 0.830:0.50:1000:300"}
EQ_CASES=${EQ_CASES:-"0.400:0.0025:1.4e-4 0.800:1e-4:3.2e-6"}

cpu() {  # cpu SECONDS-FILE COMMAND...: run, append user+system CPU seconds to the file
  local out=$1; shift
  /usr/bin/time -f "%U %S" -o "$out.t" "$@"
  awk '{ printf "%.2f\n", $1 + $2 }' "$out.t"
}
pack() {
  [ -f "$DIR/pack_nu$1.h5" ] || "$BIN/gf-pack" --quiet --grains $N --packing-fraction "$1" --seed 1 -o "$DIR/pack_nu$1.h5"
}

declare -A table
for c in $CASES; do
  IFS=: read -r nu e w m <<< "$c"
  pack "$nu"
  echo "load: $(uptime)"
  warm=$(cpu "$DIR/w" "$BIN/gf-shear" --quiet -i "$DIR/pack_nu$nu.h5" -o "$DIR/warm_${nu}_$e.h5" --rate 1e-02 \
    --restitution "$e" --steps "$w" --strain-step 1e-3 --frame-every "$w")
  s=$(cpu "$DIR/m" "$BIN/gf-shear" --quiet -i "$DIR/warm_${nu}_$e.h5" --frame -1 -o "$DIR/meas_${nu}_$e.h5" \
    --rate 1e-02 --restitution "$e" --steps "$m" --strain-step 1e-3 --frame-every "$m")
  o=$(cpu "$DIR/o" "$BIN/gf-shear" --quiet -i "$DIR/warm_${nu}_$e.h5" --frame -1 -o "$DIR/one_${nu}_$e.h5" \
    --rate 1e-02 --restitution "$e" --steps 1 --strain-step 1e-3 --frame-every 1)
  us=$(awk -v s="$s" -v o="$o" -v m="$m" -v n=$N 'BEGIN { printf "%.3g", (s - o) / ((m - 1) * n) * 1e6 }')
  echo "shear nu=$nu e=$e: warm-up $w steps $warm s, $m steps $s s, one step $o s, $us us per grain-step"
  table[$e]="${table[$e]:+${table[$e]},}$nu:$us"
done
echo "load: $(uptime)"

eq=""
for c in $EQ_CASES; do
  IFS=: read -r nu dw dt <<< "$c"
  pack "$nu"
  cpu "$DIR/ew" "$BIN/gf-shear" --quiet --rate 0 --restitution 1 -i "$DIR/pack_nu$nu.h5" -o "$DIR/eqwarm_$nu.h5" \
    --temperature 1 --dt "$dw" --steps 500 --observe-every 10 --frame-every 500 > /dev/null 2> /dev/null
  s=$(cpu "$DIR/e" "$BIN/gf-shear" --quiet --rate 0 --restitution 1 -i "$DIR/eqwarm_$nu.h5" --frame -1 \
    -o "$DIR/eq_$nu.h5" --dt "$dt" --steps 2000 --observe-every 10 --frame-every 2000)
  o=$(cpu "$DIR/o" "$BIN/gf-shear" --quiet --rate 0 --restitution 1 -i "$DIR/eqwarm_$nu.h5" --frame -1 \
    -o "$DIR/oneeq_$nu.h5" --dt "$dt" --steps 1 --frame-every 1)
  us=$(awk -v s="$s" -v o="$o" -v n=$N 'BEGIN { printf "%.3g", (s - o) / (1999 * n) * 1e6 }')
  echo "equilibrium nu=$nu: 2000 steps $s s, one step $o s, $us us per grain-step"
  eq="${eq:+$eq,}$nu:$us"
done
echo "load: $(uptime)"

for e in "${!table[@]}"; do
  echo "--frictionless $e=${table[$e]}"
done
echo "--equilibrium $eq"
