#!/usr/bin/env bash
# with_xvfb.sh COMMAND...: runs COMMAND with DISPLAY set to a private Xvfb server, stopped after
# (also when this script is interrupted or timed out: both then end).
# Xvfb picks a free display itself and names it once it accepts clients (-displayfd), so two
# of these never race for one display number (xvfb-run -a can: it guesses a free number first).
# The server runs with -noreset: by default Xvfb resets itself whenever its last client
# disconnects (the socket probe below, or pvbatch closing its first connection), and a client
# connecting during the reset is refused ("bad X server connection"); on a loaded machine that
# window is long enough to hit (2 of 6 pvbatch runs with both cores busy, none of 10 with
# -noreset). The script also waits until the server's socket accepts a connection, and runs
# COMMAND once more with a new server if it is still refused.
set -euo pipefail
dir=$(mktemp -d "${TMPDIR:-/tmp}/granflow_xvfb.XXXXXX")
server= child=
stop_server() {
  [ -n "$server" ] && kill "$server" 2> /dev/null && wait "$server" 2> /dev/null
  server=
}
stop() {
  [ -n "$child" ] && kill "$child" 2> /dev/null
  stop_server
  rm -rf "$dir"
}
trap stop EXIT
trap 'exit 143' TERM
trap 'exit 130' INT

start_server() {
  rm -f "$dir/display"
  Xvfb -displayfd 3 -nolisten tcp -noreset -screen 0 1280x1024x24 3> "$dir/display" 2> "$dir/log" &
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
  display=$(head -1 "$dir/display")
  python3 - "$display" << 'PY' || { echo "with_xvfb.sh: Xvfb :$display accepts no connection" >&2; exit 1; }
import socket, sys, time
path = "/tmp/.X11-unix/X" + sys.argv[1]
for _ in range(100):
    try:
        s = socket.socket(socket.AF_UNIX)
        s.connect(path)
        s.close()
        sys.exit(0)
    except OSError:
        time.sleep(0.1)
sys.exit(1)
PY
}

for attempt in 1 2; do
  start_server
  # In the background, so that a signal to this script is handled at once (bash runs traps
  # only between commands it waits for).
  DISPLAY=:$display "$@" 2> >(tee "$dir/stderr" >&2) &
  child=$!
  status=0
  wait "$child" || status=$?
  child=
  stop_server
  if [ "$status" -ne 0 ] && [ "$attempt" -eq 1 ] && grep -q "bad X server connection" "$dir/stderr"; then
    echo "with_xvfb.sh: the X server refused the connection; once more with a new server" >&2
    continue
  fi
  exit "$status"
done
