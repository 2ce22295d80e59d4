# Sourced by the pipeline tests: copies the source tree $1 into a fresh temporary directory
# (what git would check out, plus untracked, non-ignored files; without git, the tree minus
# build*, runs and figures), removed on exit, and cd's there. Sets `work`.
scratch_copy() {
  local src=$1
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  if git -C "$src" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    (cd "$src" && git ls-files -co --exclude-standard -z | xargs -0 tar -cf - 2>/dev/null) | tar -xf - -C "$work"
  else
    (cd "$src" && tar --exclude='./build*' --exclude=./runs --exclude=./figures -cf - .) | tar -xf - -C "$work"
  fi
  cd "$work"
}
