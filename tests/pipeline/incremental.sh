#!/usr/bin/env bash
# Pipeline test: the tiny sweep (SIZE=test) end to end in a scratch copy of the tree,
# then the incremental rules: a rebuild that leaves gf-pack's machine code alone
# (touched sources, an edited comment, a new commit = new version text) re-runs
# nothing; a change to gf-pack's code makes the packings be redone.
set -euo pipefail
src=${1:?usage: incremental.sh SOURCE_DIR}
source "$(dirname "${BASH_SOURCE[0]}")/lib/scratch_copy.bash"
scratch_copy "$src"
git init -q && git add -A && git -c user.name=t -c user.email=t@t commit -qm base

M=(make --no-print-directory -f Makefile.sweeps SIZE=test BUILD_TARGETS=gf-pack PROGRAMS=gf-pack)
fail() { echo "FAIL: $*" >&2; exit 1; }
up_to_date() { "${M[@]}" -q packings-files; }

"${M[@]}" packings >/dev/null
packs=(runs/test/pack_nu0.500_s1.h5 runs/test/pack_nu0.500_s2.h5 runs/test/pack_nu0.700_s1.h5 runs/test/pack_nu0.700_s2.h5)
for p in "${packs[@]}"; do [ -s "$p" ] || fail "$p was not made"; done
up_to_date || fail "fresh sweep is not up to date"
[ -z "$(ls -A runs/test | grep part || true)" ] || fail "partial files left in runs/test"
before=$(stat -c %Y "${packs[@]}")
sleep 1.1  # make compares seconds on some file systems

# 1. Touch every source: everything recompiles, gf-pack's code is identical.
find lib tools -name '*.cpp' -exec touch {} +
"${M[@]}" build >/dev/null
up_to_date || fail "touching sources made the packings out of date"

# 2. A new commit changes the embedded version text only.
echo "// a comment" >> lib/core/cli.cpp
git -c user.name=t -c user.email=t@t commit -qam "comment only"
"${M[@]}" build >/dev/null
up_to_date || fail "a new commit (version text) made the packings out of date"
"${M[@]}" packings >/dev/null
[ "$(stat -c %Y "${packs[@]}")" = "$before" ] || fail "packings were remade without a code change"
version=$(./build/bin/gf-pack --version)
grep -q "$(git rev-parse --short=7 HEAD)" <<<"$version" ||
  fail "version does not name the commit: '$version', HEAD $(git rev-parse --short=7 HEAD), describe $(git describe --always --dirty)"

# 3. A change to gf-pack's code: the packings must be redone.
sed -i 's/gf-pack: %zu grains/gf-pack: made %zu grains/' tools/gf-pack.cpp
"${M[@]}" build >/dev/null
if up_to_date; then fail "changing gf-pack did not invalidate the packings"; fi
"${M[@]}" packings >/dev/null
up_to_date || fail "packings not up to date after remaking them"
[ "$(stat -c %Y "${packs[@]}")" != "$before" ] || fail "packings were not remade"
echo "pipeline incremental: 1 passed, 0 failed"
