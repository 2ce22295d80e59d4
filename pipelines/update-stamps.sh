#!/usr/bin/env bash
# update-stamps.sh BIN_DIR STAMP_DIR PROGRAM...
# Writes STAMP_DIR/<program>.stamp = SHA-256 of the program's machine code, and
# touches it only when that hash changes. A PROGRAM may also be a shared library
# (BIN_DIR then its directory, <build>/lib), for the outputs of scripts that load it. The version text (section .gfversion)
# and the linker's build-id (a hash that includes it) are stripped first, so a new
# commit that leaves a program's code alone does not invalidate its outputs.
set -euo pipefail
bin=$1 stamps=$2
shift 2
mkdir -p "$stamps"
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
for prog in "$@"; do
  exe="$bin/$prog"
  [ -x "$exe" ] || { echo "update-stamps: $exe was not built" >&2; exit 1; }
  objcopy --remove-section=.gfversion --remove-section=.note.gnu.build-id "$exe" "$tmp"
  hash=$(sha256sum "$tmp" | cut -d' ' -f1)
  stamp="$stamps/$prog.stamp"
  if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$hash" ]; then
    echo "$hash" > "$stamp.new" && mv "$stamp.new" "$stamp"
    echo "stamp: $prog changed; its outputs will be remade" >&2
  fi
done
