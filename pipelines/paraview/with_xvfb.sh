#!/usr/bin/env bash
# with_xvfb.sh COMMAND...: runs COMMAND with DISPLAY set to a private Xvfb server, stopped after
# (also when this script is interrupted or timed out: both then end).
# Xvfb picks a free display itself and names it once it accepts clients (-displayfd), so two
# of these never race for one display number (xvfb-run -a can: it guesses a free number first).
set -euo pipefail
dir=$(mktemp -d "${TMPDIR:-/tmp}/granflow_xvfb.XXXXXX")
server= child=
stop() {
  [ -n "$child" ] && kill "$child" 2> /dev/null
  [ -n "$server" ] && kill "$server" 2> /dev/null && wait "$server" 2> /dev/null
  rm -rf "$dir"
}
trap stop EXIT
trap 'exit 143' TERM
trap 'exit 130' INT
Xvfb -displayfd 3 -nolisten tcp -screen 0 1280x1024x24 3> "$dir/display" 2> "$dir/log" &
server=$!
for _ in $(seq 100); do
  [ -s "$dir/display" ] && break
  kill -0 "$server" 2> /dev/null || break
  sleep 0.1
done
if [ ! -s "$dir/display" ]; then
  echo "with_xvfb.sh: Xvfb did not start:" >&2
  cat "$dir/log" >&2
  exit 1
fi
# In the background, so that a signal to this script is handled at once (bash runs traps only
# between commands it waits for).
DISPLAY=:$(head -1 "$dir/display") "$@" &
child=$!
status=0
wait "$child" || status=$?
child=
exit "$status"
