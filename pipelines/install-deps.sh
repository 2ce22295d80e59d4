#!/usr/bin/env bash
# install-deps.sh PACKAGE...: installs the missing Debian packages (as root), or
# prints the exact command to run and fails.
set -euo pipefail
missing=()
for pkg in "$@"; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "deps: missing Debian packages: ${missing[*]}" >&2
if [ "$(id -u)" -eq 0 ]; then
  export DEBIAN_FRONTEND=noninteractive
  # An empty package list (fresh machine) makes install fail: update first.
  apt-get update -qq
  apt-get install -y -qq "${missing[@]}"
else
  echo "deps: run as root:  sudo apt-get update && sudo apt-get install -y ${missing[*]}" >&2
  exit 1
fi
