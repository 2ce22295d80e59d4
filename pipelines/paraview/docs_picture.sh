#!/usr/bin/env bash
# Re-makes the picture of docs/programs/gf-xdmf.md: a short frictionless shear flow of 2000
# grains at nu = 0.8 (gf-pack, gf-shear), its XDMF (gf-xdmf) and the last frame rendered by
# Debian's ParaView (force_chains.py under a private Xvfb, with_xvfb.sh).
#   bash pipelines/paraview/docs_picture.sh [BIN_DIR [OUT.png]]   (defaults: build/bin, docs/images/paraview_force_chains.png)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-build/bin}
out=${2:-docs/images/paraview_force_chains.png}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/granflow_picture.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
"$bin/gf-pack" --grains 2000 --packing-fraction 0.8 --seed 1 --quiet -o "$tmp/pack.h5"
"$bin/gf-shear" -i "$tmp/pack.h5" -o "$tmp/flow.h5" --rate 1 --strain 0.5 --frame-every 100 --quiet
"$bin/gf-xdmf" -i "$tmp/flow.h5"
ls -l "$tmp/flow.h5" "$tmp/flow.xdmf2" >&2
bash "$here/with_xvfb.sh" pvbatch "$here/force_chains.py" "$tmp/flow.xdmf2" "$out" --size 700 700 2>&1 | grep '^force_chains:'
