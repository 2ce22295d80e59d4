#!/usr/bin/env bash
# install.sh SOURCE_DIR BUILD_DIR VERSION CMAKE CXX BINDIR LIBDIR INCLUDEDIR MANDIR: the install
# rules (cmake/Install.cmake, docs/install.md) as a user meets them; the last four are the
# build's CMAKE_INSTALL_<dir>. Installs the build into a scratch prefix, checks that every
# program, library, header, package file and man page is there and that no text file there names
# the build or source tree, renders each man page (`man -l`: no warning, a line for every option
# of the program's --help and of each gf-stz command), makes a trajectory with the installed
# gf-pack and gf-shear, builds tests/install/consumer against the installed package twice, with
# find_package(granflow VERSION) and with pkg-config, and runs both on it: their grain count,
# frame count and last step must be h5dump's, their library version the one `gf-shear --version`
# prints. Last, links all of libgranflow.a with pkg-config's flags. Run by ctest as
# install.Package; needs the whole build (`all`). Exit 77 (skipped) when an install directory is
# absolute: the install would not stay inside the scratch prefix.
set -euo pipefail
src=$(cd "$1" && pwd) build=$(cd "$2" && pwd) version=$3 cmake=$4 cxx=$5
bindir=$6 libdir=$7 includedir=$8 mandir=$9
for dir in "$bindir" "$libdir" "$includedir" "$mandir"; do
  if [[ $dir == /* ]]; then
    echo "install test: skipped: an absolute install directory ($dir) is outside any --prefix" >&2
    exit 77
  fi
done
consumer=$src/tests/install/consumer
tmp=$(mktemp -d "${TMPDIR:-/tmp}/granflow-install.XXXXXX")
# cmake --install lists what it wrote in BUILD_DIR/install_manifest.txt: the user's own list (of
# a real install, which `xargs rm < install_manifest.txt` undoes) is put back afterwards.
manifest=$build/install_manifest.txt
[ ! -f "$manifest" ] || cp -p "$manifest" "$tmp/manifest.kept"
cleanup() {
  if [ -f "$tmp/manifest.kept" ]; then cp -p "$tmp/manifest.kept" "$manifest"; else rm -f "$manifest"; fi
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() {
  echo "install test: $*" >&2
  exit 1
}
# Run a command quietly; on failure show its output and fail with the message.
quiet() {
  local what=$1
  shift
  "$@" > "$tmp/log" 2>&1 || { cat "$tmp/log" >&2; fail "$what failed: $*"; }
}
prefix=$tmp/prefix

# ---------------------------------------------------------------- install, and what it wrote
"$cmake" --install "$build" --prefix "$prefix" > "$tmp/install.log" 2>&1 || {
  cat "$tmp/install.log" >&2
  fail "cmake --install failed (is the whole build made? cmake --build $build)"
}
programs=()
for f in "$src"/tools/gf-*.cpp; do programs+=("$(basename "$f" .cpp)"); done
expected=("$libdir/libgranflow.a" "$libdir/libgranflow_statistics.so" "$libdir/pkgconfig/granflow.pc"
          "$libdir/cmake/granflow/granflowConfig.cmake" "$libdir/cmake/granflow/granflowConfigVersion.cmake"
          "$libdir/cmake/granflow/granflowTargets.cmake")
for p in "${programs[@]}"; do expected+=("$bindir/$p" "$mandir/man1/$p.1"); done
# The Python package, every module and the statistics library beside them.
pythondir=${GRANFLOW_INSTALL_PYTHONDIR:-lib/python3/dist-packages}
expected+=("$pythondir/granflow/libgranflow_statistics.so")
for f in "$src"/python/granflow/*.py; do expected+=("$pythondir/granflow/$(basename "$f")"); done
# Every header of lib/, in its folder.
while IFS= read -r h; do
  expected+=("$includedir/granflow/$h")
done < <(cd "$src/lib" && find . -name '*.hpp' -o -name '*.h' | sed 's|^\./||')
for f in "${expected[@]}"; do [ -f "$prefix/$f" ] || fail "not installed: $f"; done
for p in "${programs[@]}"; do [ -x "$prefix/$bindir/$p" ] || fail "not executable: $bindir/$p"; done
named=$(grep -rlIF -e "$build" -e "$src" "$prefix" || true)
[ -z "$named" ] || fail "installed files naming the build or source tree: $named"

# ---------------------------------------------------------------- man pages
# Long options a --help text lists (lib/core/cli.cpp's option lines).
options() { sed -n 's/^  \(-[A-Za-z0-9], \|    \)--\([a-z0-9][a-z0-9-]*\)\( <[^>]*>\)\{0,1\}$/\2/p'; }
for p in "${programs[@]}"; do
  page=$prefix/$mandir/man1/$p.1
  # Wide lines: no option broken or hyphenated across lines.
  LC_ALL=C.UTF-8 MANWIDTH=1000 man --warnings -l "$page" > "$tmp/page.txt" 2> "$tmp/page.err" ||
    fail "man -l $mandir/man1/$p.1 failed: $(cat "$tmp/page.err")"
  [ ! -s "$tmp/page.err" ] || fail "man -l $mandir/man1/$p.1 warns: $(cat "$tmp/page.err")"
  for section in NAME SYNOPSIS DESCRIPTION OPTIONS "SEE ALSO"; do
    grep -q "^$section\$" "$tmp/page.txt" || fail "$mandir/man1/$p.1 has no section $section"
  done
  grep -qE "^ +$p +- " "$tmp/page.txt" || fail "$mandir/man1/$p.1: its NAME does not name $p"
  help=$("$prefix/$bindir/$p" --help)
  listed=$(options <<< "$help")
  # A program's commands ("Commands:" block, gf-stz): each a section with its options.
  # shellcheck disable=SC2013  # command names are words
  for command in $(sed -n '/^Commands:$/,/^$/s/^  \([a-z][a-z0-9-]*\)  .*/\1/p' <<< "$help"); do
    grep -q "^COMMAND ${command^^}\$" "$tmp/page.txt" || fail "$mandir/man1/$p.1 has no section for command $command"
    listed+=$'\n'$("$prefix/$bindir/$p" "$command" --help | options)
  done
  [ -n "$listed" ] || fail "$p --help lists no option"
  # Each option heads a line of its own (help2man's tag), its description below.
  for option in $listed; do
    grep -qE -- "^ +(-[A-Za-z0-9], )?--$option( <[^>]*>)?\$" "$tmp/page.txt" ||
      fail "$mandir/man1/$p.1 has no line for --$option"
  done
done

# ---------------------------------------------------------------- the installed programs
cd "$tmp"
version_text=$("$prefix/$bindir/gf-shear" --version)
version_line=${version_text%%$'\n'*}
[[ $version_line == "gf-shear $version ("*")" ]] ||
  fail "gf-shear --version printed '$version_line' first, not 'gf-shear $version (...)'"
[[ $version_text == *BSD-3-Clause* ]] || fail "gf-shear --version does not name the licence: '$version_text'"
quiet "installed gf-pack" "$prefix/$bindir/gf-pack" -o pack.h5 --grains 64 --packing-fraction 0.8 --seed 1 --quiet
quiet "installed gf-shear" "$prefix/$bindir/gf-shear" -i pack.h5 -o shear.h5 --strain 0.1 --frame-every 10 --quiet
# What the consumer must find: h5dump's shape of the positions ([frames][grains][2]) and last step.
shape=$(h5dump -H -d /particles/grains/position/value shear.h5 |
  sed -n 's/.*DATASPACE *SIMPLE { ( \([0-9]*\), \([0-9]*\), 2 ).*/\1 \2/p')
[ -n "$shape" ] || fail "h5dump shows no /particles/grains/position/value in shear.h5"
read -r frames grains <<< "$shape"
last_step=$(h5dump -d /particles/grains/position/step -s $((frames - 1)) -c 1 shear.h5 |
  sed -n 's/^ *([0-9]*): \([0-9]*\)$/\1/p')
if [ "$grains" != 64 ] || [ "$frames" -lt 2 ] || [ -z "$last_step" ]; then
  fail "h5dump: $grains grains, $frames frames, last step '$last_step' in shear.h5"
fi
want=$(printf 'granflow %s\ngrains %s frames %s last step %s' \
  "${version_line#gf-shear }" "$grains" "$frames" "$last_step")

# ---------------------------------------------------------------- an outside project: CMake
quiet "configuring the consumer" "$cmake" -S "$consumer" -B consumer-build -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_CXX_COMPILER="$cxx" -DGRANFLOW_VERSION="$version" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON
found=$(sed -n 's/^granflow_DIR:PATH=//p' consumer-build/CMakeCache.txt)
[ "$found" = "$prefix/$libdir/cmake/granflow" ] || fail "the consumer found granflow in '$found', not in the prefix"
! grep -qF -e "$src/lib" -e "$build/" consumer-build/compile_commands.json ||
  fail "the consumer compiles with lib/ or the build tree: $(cat consumer-build/compile_commands.json)"
quiet "building the consumer" "$cmake" --build consumer-build
got=$(consumer-build/consumer shear.h5) || fail "the consumer (CMake) failed on shear.h5"
[ "$got" = "$want" ] || fail "the consumer (CMake) printed"$'\n'"$got"$'\n'"instead of"$'\n'"$want"

# ---------------------------------------------------------------- an outside project: pkg-config
export PKG_CONFIG_PATH=$prefix/$libdir/pkgconfig
[ "$(pkg-config --variable=pcfiledir granflow)" = "$prefix/$libdir/pkgconfig" ] ||
  fail "pkg-config finds granflow.pc in '$(pkg-config --variable=pcfiledir granflow)', not in the prefix"
[ "$(pkg-config --modversion granflow)" = "$version" ] ||
  fail "pkg-config --modversion granflow: $(pkg-config --modversion granflow), not $version"
flags=$(pkg-config --cflags --libs granflow) || fail "pkg-config --cflags --libs granflow failed"
# Sources before the libraries: the linker takes from libgranflow.a what the objects before it need.
# shellcheck disable=SC2086
quiet "compiling the consumer with pkg-config's flags" "$cxx" "$consumer/consumer.cpp" $flags -o consumer-pc
got=$(./consumer-pc shear.h5) || fail "the consumer (pkg-config) failed on shear.h5"
[ "$got" = "$want" ] || fail "the consumer (pkg-config) printed"$'\n'"$got"$'\n'"instead of"$'\n'"$want"
# The consumer needs only part of libgranflow.a (no FFTW, no GSL): link every object of it, so
# that a library missing from the Libs or Requires of granflow.pc is an undefined reference.
printf 'int main() {}\n' > whole.cpp
libs=$(pkg-config --libs granflow)
# shellcheck disable=SC2086
quiet "linking all of libgranflow.a with \`pkg-config --libs granflow\`" "$cxx" whole.cpp \
  -Wl,--whole-archive "$prefix/$libdir/libgranflow.a" -Wl,--no-whole-archive $libs -o whole

# ---------------------------------------------------------------- the installed Python package
# Outside the repository (no PYTHONPATH into it, no GRANFLOW_BUILD): the installed package reads
# the trajectory and finds its own statistics library.
python_out=$(cd "$tmp" && env -u GRANFLOW_BUILD PYTHONPATH="$prefix/$pythondir" /usr/bin/python3 -c '
import sys, numpy as np, granflow, granflow.statistics as st
with granflow.Trajectory("shear.h5") as t:
    print(granflow.__file__, st.library_path(), len(t), len(t[-1].position), t[-1].step)
print(st.blocking_error(np.arange(64.0) % 2)[0] >= 0)
' 2>&1) || fail "the installed Python package failed: $python_out"
read -r py_file py_library py_frames py_grains py_step py_ok <<< "${python_out//$'\n'/ }"
[[ $py_file == "$prefix/$pythondir/granflow/"* ]] || fail "python imported granflow from $py_file, not the prefix"
[ "$py_library" = "$prefix/$pythondir/granflow/libgranflow_statistics.so" ] ||
  fail "granflow.statistics loads $py_library, not the installed package's library"
[ "$py_grains $py_frames $py_step $py_ok" = "$grains $frames $last_step True" ] ||
  fail "the installed Python package read $py_grains grains, $py_frames frames, last step $py_step" \
       "($py_ok), h5dump $grains, $frames, $last_step"

echo "install test: OK: ${#expected[@]} files, ${#programs[@]} man pages, the Python package," \
  "the consumer by CMake and pkg-config (${got//$'\n'/; })"
