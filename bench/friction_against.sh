#!/usr/bin/env bash
# The frictional solver against an earlier commit's, side by side: builds bench_friction of
# COMMIT (default 0827026, the build issue 24 was filed against, whose default frictional solver
# is Gauss–Seidel alone) from `git archive`, then runs the default solver (case .../1/) of that
# binary and of this tree's, alternating, ROUNDS times, and prints CPU seconds per unit strain,
# sweeps per step and the ratio of the best of each. See docs/performance.md, "Frictional flows".
#
#   bash bench/friction_against.sh [COMMIT]
#
# Environment (defaults in brackets):
#   FILTER ['BM_Friction/1000/(700|760|780|800)/1/|BM_Friction/10000/(760|780)/1/']
#                     cases run by both binaries (bench_friction's --benchmark_filter)
#   ROUNDS [2]        alternations (old, new, old, new, ...); the best s/strain of each is kept
#   BUILD [build]     this tree's build directory (configured as Release if new; bench_friction is built there)
#   OUT [build/friction-against]  the old sources, their build, raw outputs and each run's stderr (never committed)
# Each binary warms every (N, ν) up with its own default solver, so the two time the same steps
# from statistically alike, not identical, states: the ratio carries that spread (about 10 %
# at N = 10³, more at ν = 0.80), which is why the docs quote it as measured, not to the per cent.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
COMMIT="${1:-0827026}"
FILTER="${FILTER:-BM_Friction/1000/(700|760|780|800)/1/|BM_Friction/10000/(760|780)/1/}"
ROUNDS="${ROUNDS:-2}"
BUILD="${BUILD:-$ROOT/build}"
OUT="${OUT:-$ROOT/build/friction-against}"
export OMP_NUM_THREADS=1
log() { echo "[friction-against $(date +%H:%M:%S)] $*" >&2; }

git -C "$ROOT" rev-parse --verify --quiet "$COMMIT^{commit}" >/dev/null || {
  echo "friction_against.sh: '$COMMIT' is not a commit of $ROOT" >&2
  exit 2
}
case "$ROUNDS" in '' | *[!0-9]* | 0) echo "friction_against.sh: ROUNDS must be a positive integer" >&2; exit 2 ;; esac
mkdir -p "$OUT"
SRC="$OUT/src-$COMMIT"
OLD_BUILD="$OUT/build-$COMMIT"
if [ ! -d "$SRC" ]; then
  log "sources of $COMMIT in $SRC"
  mkdir -p "$SRC.partial"
  git -C "$ROOT" archive "$COMMIT" | tar -x -C "$SRC.partial"
  mv "$SRC.partial" "$SRC"
fi
log "building bench_friction of $COMMIT and of this tree"
cmake -S "$SRC" -B "$OLD_BUILD" -DCMAKE_BUILD_TYPE=Release >"$OUT/build.log" 2>&1
cmake --build "$OLD_BUILD" -j2 --target bench_friction >>"$OUT/build.log" 2>&1
# This tree's build is configured only if it is not yet: a user's build keeps its settings.
[ -f "$BUILD/CMakeCache.txt" ] || cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >>"$OUT/build.log" 2>&1
grep -q '^CMAKE_BUILD_TYPE:STRING=Release$' "$BUILD/CMakeCache.txt" ||
  log "warning: $BUILD is not a Release build; its timings are not comparable"
cmake --build "$BUILD" -j2 --target bench_friction >>"$OUT/build.log" 2>&1
NEW_LABEL="$(git -C "$ROOT" rev-parse --short HEAD)$(git -C "$ROOT" diff --quiet HEAD -- lib bench || echo +)"

RAW="$OUT/timings.tsv"  # label round case s/strain sweeps
: >"$RAW"
for round in $(seq "$ROUNDS"); do
  for side in old new; do
    if [ "$side" = old ]; then bin="$OLD_BUILD/bench/bench_friction" label="$COMMIT"
    else bin="$BUILD/bench/bench_friction" label="$NEW_LABEL"; fi
    log "round $round: $label"
    "$bin" --benchmark_filter="$FILTER" 2>"$OUT/$side-$round.err" | tee "$OUT/$side-$round.txt" |
      awk -v label="$side" -v round="$round" '/^BM_Friction\// {
        s = ""; w = ""
        for (i = 2; i <= NF; ++i) {
          if ($i ~ /^s\/strain=/) s = substr($i, 10)
          if ($i ~ /^sweeps=/) w = substr($i, 8)
        }
        sub(/\/iterations:.*/, "", $1)
        print label "\t" round "\t" $1 "\t" s "\t" w
      }' >>"$RAW"
  done
done

# The best (smallest) s/strain of each side per case, with the sweeps of that run; bench's
# counters may print thousands as 1.2k.
awk -F'\t' '
  function num(x) { return x ~ /k$/ ? 1000 * substr(x, 1, length(x) - 1) : x + 0 }
  {
    k = $1 SUBSEP $3
    if (!(k in best) || num($4) < best[k]) { best[k] = num($4); sweeps[k] = num($5) }
    if ($1 == "new") cases[$3] = 1
  }
  END {
    for (c in cases) {
      o = "old" SUBSEP c; n = "new" SUBSEP c
      if (o in best) printf "%s\t%.3f\t%.1f\t%.3f\t%.1f\t%.2f\n", c, best[o], sweeps[o], best[n], sweeps[n], best[o] / best[n]
    }
  }' "$RAW" | sort -t/ -k2,2n -k3,3n |
  awk -F'\t' -v old="$COMMIT" -v new="$NEW_LABEL" '
    BEGIN { printf "%-22s %18s %9s %18s %9s %7s\n", "case (N/nu/solver)", "s/strain " old, "sweeps", "s/strain " new, "sweeps", "ratio" }
    { printf "%-22s %18s %9s %18s %9s %7s\n", $1, $2, $3, $4, $5, $6 }'
