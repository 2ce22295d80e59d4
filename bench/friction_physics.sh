#!/usr/bin/env bash
# Same physics with and without the exact frictional cluster solves: the quick size's μ = 0.4
# shear runs at ν = 0.70 and 0.76, e = 0 and 0.5 (N = 1000, the pipeline's commands), run by
# gf-shear with its default solver and with --no-cluster-solves (Gauss–Seidel alone), then the
# steady p/γ̇², s/p, T/γ̇² of both with block errors (bench/peer/peer.py stats) and their
# difference in combined standard errors. See docs/performance.md, "Frictional flows".
#
#   bash bench/friction_physics.sh [BUILD_DIR] [OUT_DIR]     (defaults: build, build/friction-physics)
#   CASES="0.700:20:1000:2:2" SEEDS="2 3" E="0.50" bash bench/friction_physics.sh ...   other packings,
#       restitutions and lengths (ν:strain:frame-every:steady-from:block per case)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="$(cd "${1:-$ROOT/build}" && pwd)/bin"
OUT="${2:-$ROOT/build/friction-physics}"
PY=/usr/bin/python3
export OMP_NUM_THREADS=1
mkdir -p "$OUT"
cd "$OUT"
# ν, strain, frames every, steady part from, block (strain units): the pipeline's long runs at 0.70.
CASES="${CASES:-0.700:40:160:5:5 0.760:5:20:1:0.5}"
for c in $CASES; do
  IFS=: read -r nu strain every skip block <<<"$c"
  for seed in ${SEEDS:-1}; do
    pack="pack_nu${nu}_s$seed.h5"
    [ -f "$pack" ] || "$BIN/gf-pack" --quiet --grains 1000 --packing-fraction "$nu" --seed "$seed" -o "$pack"
    for e in ${E:-0.00 0.50}; do
      for solver in default no-cluster-solves; do
        out="shear_nu${nu}_e${e}_s${seed}_strain${strain}_$solver.h5"
        extra=()
        [ "$solver" = default ] || extra=(--no-cluster-solves)
        if [ ! -f "$out" ]; then
          /usr/bin/time -f "%U" -o "$out.cpu" "$BIN/gf-shear" --quiet -i "$pack" -o "$out" --rate 1e-02 \
            --restitution "$e" --friction 0.40 --seed 1 --strain "$strain" --strain-step 1e-3 --frame-every "$every" \
            "${extra[@]}"
        fi
        $PY "$ROOT/bench/peer/peer.py" stats "$out" --skip "$skip" --block "$block" >"$out.json"
      done
    done
  done
done
$PY - <<'PY'
import glob, json, math, os, h5py
print("| ν | e | packing seed | strain | solver | CPU s | sweeps/step | p/γ̇² | s/p | T/γ̇² |")
print("|---|---|---|---|---|---|---|---|---|---|")
rows = {}
for f in sorted(glob.glob("shear_nu*_e*_s*_strain*_*.h5")):
    if not os.path.exists(f + ".json"):  # a case of another invocation, not measured yet
        continue
    nu, e, seed, strain, solver = f[len("shear_nu"):-3].split("_", 4)
    key = (nu, e[1:], seed[1:], strain[len("strain"):])
    st = json.load(open(f + ".json"))
    cpu = float(open(f + ".cpu").read().split()[-1])
    sweeps = h5py.File(f, "r")["run"].attrs["mean_iterations"]
    rows[key + (solver,)] = st
    print("| " + " | ".join(key) + f" | {solver} | {cpu:.1f} | {sweeps:.1f} | {st['p']:.2f} ± {st['p_err']:.2f} | "
          f"{st['mu']:.4f} ± {st['mu_err']:.4f} | {st['T']:.3f} ± {st['T_err']:.3f} |")
print()
print("| ν | e | packing seed | strain | Δp/σ | Δ(s/p)/σ | ΔT/σ |")
print("|---|---|---|---|---|---|---|")
for key, a in sorted(rows.items()):
    if key[-1] != "default" or key[:-1] + ("no-cluster-solves",) not in rows:
        continue
    b = rows[key[:-1] + ("no-cluster-solves",)]
    z = [(a[k] - b[k]) / math.hypot(a[k + "_err"], b[k + "_err"]) for k in ("p", "mu", "T")]
    print("| " + " | ".join(key[:-1]) + " | " + " | ".join(f"{x:+.2f}" for x in z) + " |")
PY
