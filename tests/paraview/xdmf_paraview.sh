#!/usr/bin/env bash
# paraview.GfXdmf: a small sheared flow through gf-xdmf into Debian's ParaView.
#   bash tests/paraview/xdmf_paraview.sh SOURCE_DIR BIN_DIR
# 1. gf-pack + gf-shear make a trajectory (300 grains, nu = 0.8, frictionless, 4 frames);
#    gf-xdmf describes it; the pair is then moved to another directory (relative reference).
# 2. pvpython (check_xdmf.py) opens the XDMF with the Xdmf Reader and compares, for two frames,
#    the points, cells and arrays with what h5py reads from the .h5 (xdmf_expected.py): grains,
#    every contact segment r_i -> r_i - branch (contacts across the periodic and Lees-Edwards
#    boundaries included), the forces, the box. Also a packing (no contacts), an incline run
#    and a file whose frames hold 0 and 1 contacts (the XDMF's special forms).
# 3. A deliberately wrong XDMF (segments to r_i + branch) must fail the same check.
# 4. pvbatch renders disks and force chains (pipelines/paraview/force_chains.py) under a
#    private Xvfb (pipelines/paraview/with_xvfb.sh); the PNG must not be blank.
# Exit 77 (skipped) only when ParaView (pvpython, pvbatch) or Xvfb is not installed.
set -euo pipefail
src=$1 bin=$2
here=$src/tests/paraview
python=/usr/bin/python3
for tool in pvpython pvbatch Xvfb; do
  if ! command -v "$tool" > /dev/null; then
    echo "paraview.GfXdmf: SKIPPED: $tool not found (Debian packages paraview python3-paraview xvfb;" \
         "make -f Makefile.sweeps test installs them)" >&2
    exit 77
  fi
done
tmp=$(mktemp -d "${TMPDIR:-/tmp}/granflow_paraview.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
start=$(date +%s)
# ParaView's own messages (its logger, the XDMF library) go to a log shown on failure only.
quietly() {
  local log=$tmp/last.log
  if ! timeout 90 "$@" > "$log" 2>&1; then
    grep -v '^ *[0-9]* *0x' "$log" | tail -40 >&2
    return 1
  fi
  grep '^check_xdmf:\|^force_chains:' "$log" || true
}

cd "$tmp"
"$bin/gf-pack" --grains 300 --packing-fraction 0.8 --seed 4 --quiet -o pack.h5
"$bin/gf-shear" -i pack.h5 -o flow.h5 --rate 1 --steps 300 --frame-every 100 --quiet
"$bin/gf-xdmf" -i flow.h5 --quiet
"$bin/gf-xdmf" -i pack.h5 -o pack.xdmf --quiet
# An incline run: open in y, base grains fixed, times in tau.
"$bin/gf-pack" --incline --width 10 --height 5 --seed 3 --quiet -o slope.h5
"$bin/gf-incline" -i slope.h5 -o incline.h5 --angle 20 --time 10 --frame-every 2500 --quiet 2> incline.log
"$bin/gf-xdmf" -i incline.h5 --quiet
mkdir moved && mv flow.h5 flow.xdmf2 moved/

# The frames checked: the second and the last one, plus the first (no contacts: a shear run's
# start) in the file below.
$python "$here/xdmf_expected.py" moved/flow.h5 flow.json 1 3
$python "$here/xdmf_expected.py" pack.h5 pack.json 0
$python "$here/xdmf_expected.py" incline.h5 incline.json 1 2
mkdir other && cd other
quietly pvpython "$here/check_xdmf.py" ../moved/flow.xdmf2 ../flow.json
quietly pvpython "$here/check_xdmf.py" ../pack.xdmf ../pack.json
quietly pvpython "$here/check_xdmf.py" ../incline.xdmf2 ../incline.json
cd ..

# Frames of 0 and 1 contacts: a copy whose frame 1 keeps only its first contact row.
cp moved/flow.h5 sparse.h5
$python - << 'PY'
import h5py
with h5py.File("sparse.h5", "r+") as f:
    offset = f["/contacts/frame_offset"]
    offset[2] = offset[1] + 1
PY
"$bin/gf-xdmf" -i sparse.h5 --quiet
$python "$here/xdmf_expected.py" sparse.h5 sparse.json 0 1 2
quietly pvpython "$here/check_xdmf.py" sparse.xdmf2 sparse.json

# The check must see a wrong geometry: segments to r_i + branch.
sed 's/(\$0\[\$1 \* 2\] - \$2)/($0[$1 * 2] + $2)/; s/(\$0\[\$1 \* 2 + 1\] - \$3)/($0[$1 * 2 + 1] + $3)/' \
  moved/flow.xdmf2 > moved/wrong.xdmf2
if cmp -s moved/flow.xdmf2 moved/wrong.xdmf2; then
  echo "paraview.GfXdmf: the wrong XDMF was not made (the geometry expression changed?)" >&2
  exit 1
fi
if timeout 90 pvpython "$here/check_xdmf.py" moved/wrong.xdmf2 flow.json > wrong.log 2>&1; then
  echo "paraview.GfXdmf: check_xdmf.py accepted segments to r_i + branch" >&2
  exit 1
fi
grep -q 'contact segments are not r_i to r_i - branch' wrong.log || {
  echo "paraview.GfXdmf: the wrong XDMF failed for another reason:" >&2
  grep '^check_xdmf' wrong.log >&2 || tail -5 wrong.log >&2
  exit 1
}

# A private X server (with_xvfb.sh: no fixed display number, no race with other servers).
quietly bash "$src/pipelines/paraview/with_xvfb.sh" pvbatch "$src/pipelines/paraview/force_chains.py" \
  moved/flow.xdmf2 chains.png --size 600 600
$python - << 'PY'
import sys
import matplotlib.image
import numpy as np
image = matplotlib.image.imread("chains.png")[..., :3]
pixels = image.reshape(-1, 3)
drawn = np.mean(np.any(pixels < 0.95, axis=1))                       # not the white background
colours = len(np.unique((pixels * 255).astype(np.uint8), axis=0))
dark = np.mean(np.all(pixels < 0.4, axis=1))                          # strong chains, the box
warm = np.mean((pixels[:, 0] > 0.7) & (pixels[:, 2] < 0.5))           # weak chains: yellow, orange
print(f"chains.png: {drawn:.0%} drawn, {colours} colours, {dark:.1%} dark, {warm:.1%} yellow-orange")
if drawn < 0.3 or colours < 20 or dark < 0.002 or warm < 0.002:
    sys.exit("paraview.GfXdmf: the picture looks blank or lacks disks or force chains")
PY
echo "paraview.GfXdmf: passed in $(( $(date +%s) - start )) s"
