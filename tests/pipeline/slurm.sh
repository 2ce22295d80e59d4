#!/usr/bin/env bash
# Pipeline test: the tiny sweep (SIZE=test, every chapter) through a real single-node Slurm
# (Debian's slurm-wlm and munge, daemons in a scratch directory, stopped at the end whatever
# happens), against the same sweep run locally:
#  1. the sweep inside `salloc`, LAUNCH='srun -n1 -c1', with one job step killed (scancel)
#     while its gf-shear runs: make fails, the killed run leaves no file make would trust,
#     and every other output is byte-identical to the local one;
#  2. the documented batch script (pipelines/slurm/sweep.sbatch) finishes the sweep: it redoes
#     the killed run and what depended on it, nothing that was already made; then every output
#     is byte-identical to the local sweep's and `make -q` finds nothing to redo;
#  3. a run inside a job step stopped the way a time limit stops it (SIGTERM) leaves a
#     checkpoint, and the next sweep resumes it (--resume) to the same trajectory and parameters;
#  4. a rule that ignores LAUNCH fails: the programs are called through guards that refuse to
#     run outside a Slurm job step, and a copy of the tree whose packing rule drops $(LAUNCH)
#     fails; every recipe that calls a gf-* program starts with $(LAUNCH);
#  5. with the daemons down, the sweep fails at once with Slurm's own line (exit 2), and
#     writes nothing.
# Usage: slurm.sh SOURCE_DIR BUILD_DIR (the programs of BUILD_DIR/bin are not rebuilt).
set -euo pipefail
src=${1:?usage: slurm.sh SOURCE_DIR BUILD_DIR}
build=$(cd "${2:?usage: slurm.sh SOURCE_DIR BUILD_DIR}" && pwd)
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
source "$here/lib/scratch_copy.bash"
source "$here/lib/slurm.bash"
fail() { echo "FAIL: $*" >&2; exit 1; }
programs=(gf-pack gf-shear gf-incline gf-correlate gf-kinetic gf-network gf-stz)
for p in "${programs[@]}"; do [ -x "$build/bin/$p" ] || fail "$build/bin/$p is not built"; done

scratch_copy "$src"
tree=$work
scratch=$(mktemp -d)  # the daemons, the guards, a tarball of the tree
chmod 755 "$scratch"  # munged wants every directory above its socket open to all
trap 'slurm_down; rm -rf "$tree" "$scratch"' EXIT
tar -cf "$scratch/tree.tar" .
copy_tree() { mkdir -p "$1" && tar -xf "$scratch/tree.tar" -C "$1"; }
# Both sweeps take the same relative paths (recorded in the outputs' provenance) and the
# stamps of the same programs.
stamps() {
  bash pipelines/update-stamps.sh "$build/bin" stamps "${programs[@]}" 2>/dev/null
  bash pipelines/update-stamps.sh "$build/lib" stamps libgranflow_statistics.so 2>/dev/null
}
M=(make --no-print-directory -f Makefile.sweeps SIZE=test STAMPS=stamps "GRANFLOW_BUILD=$build"
   PYTHON=/usr/bin/python3)
# Every output of a sweep, temporaries included, as "path size mtime(ns)".
listing() { { find runs figures -type f -printf '%p %s %T@\n' 2>/dev/null || true; } | sort; }
outputs() { { find runs figures -type f 2>/dev/null || true; } | sort; }
same_as_local() {  # FILE...: byte-identical to the local sweep's
  local f
  for f in "$@"; do cmp -s "$f" "$tree/local/$f" || fail "$f differs from the local sweep's"; done
}

# ---------------------------------------------------------------- the local reference
copy_tree local
(cd local && stamps && "${M[@]}" "BIN=$build/bin" -j2 quick-files >../local.log 2>&1) ||
  { tail -n 20 local.log >&2; fail "the local sweep failed"; }
local_files=$(cd local && find runs figures -type f | sort)
[ "$(wc -l <<<"$local_files")" -ge 60 ] || fail "the local sweep made only $(wc -l <<<"$local_files") files"

# ---------------------------------------------------------------- Slurm
slurm_up "$scratch/slurm" || exit 1
# Guards: each program runs only inside a job step (srun sets SLURM_STEP_ID; salloc's shell
# and a batch script do not). It execs the real program under its own path, so the command
# line the outputs record is the local sweep's. For the output named by GUARD_STOP_OUTPUT it
# waits until the run has its temporary file, stops it (SIGSTOP) and writes
# "<job>.<step> <pid>" to GUARD_STOP_MARKER, so the test can kill or signal it mid-run.
mkdir "$scratch/bin"
for p in "${programs[@]}"; do
  cat >"$scratch/bin/$p" <<GUARD
#!/usr/bin/env bash
[ -n "\${SLURM_STEP_ID:-}" ] || { echo "guard: $p run outside a Slurm job step (a rule ignores LAUNCH)" >&2; exit 3; }
out=
prev=
for a in "\$@"; do [ "\$prev" = -o ] && out=\$a; prev=\$a; done
if [ -z "\${GUARD_STOP_OUTPUT:-}" ] || [ "\$out" != "\$GUARD_STOP_OUTPUT" ] || [ -e "\$GUARD_STOP_MARKER" ]; then
  exec "$build/bin/$p" "\$@"
fi
"$build/bin/$p" "\$@" &
pid=\$!
for i in \$(seq 4000); do
  compgen -G "\$(dirname "\$out")/.\$(basename "\$out").part-*" >/dev/null && break
  kill -0 \$pid 2>/dev/null || break
  sleep 0.005
done
kill -STOP \$pid 2>/dev/null && echo "\$SLURM_JOB_ID.\$SLURM_STEP_ID \$pid" >"\$GUARD_STOP_MARKER.new" &&
  mv "\$GUARD_STOP_MARKER.new" "\$GUARD_STOP_MARKER"
# A signal to the step reaches the stopped run too (the test continues it).
trap 'kill -TERM \$pid 2>/dev/null' TERM
rc=0
while kill -0 \$pid 2>/dev/null; do wait \$pid && rc=0 || rc=\$?; done
exit \$rc
GUARD
  chmod +x "$scratch/bin/$p"
done
C=("${M[@]}" "BIN=$scratch/bin" "LAUNCH=srun -n1 -c1")

no_guard_refusal() {  # LOG: no program ran outside a job step
  ! grep -q "^guard:" "$1" || fail "rules ignore LAUNCH: $(grep "^guard:" "$1" | sort -u)"
}
# Starts `make ARGS` in the background with one run stopped mid-way (GUARD_STOP_OUTPUT=$1),
# waits for the stop; sets make_pid, stopped_step, stopped_pid.
start_with_stop() {
  local target=$1 log=$2 i
  shift 2
  rm -f "$scratch/stopped"
  GUARD_STOP_OUTPUT=$target GUARD_STOP_MARKER=$scratch/stopped "$@" >"$log" 2>&1 &
  make_pid=$!
  for i in $(seq 1200); do
    [ -s "$scratch/stopped" ] && break
    kill -0 $make_pid 2>/dev/null || break
    sleep 0.1
  done
  no_guard_refusal "$log"
  [ -s "$scratch/stopped" ] || { tail -n 20 "$log" >&2; fail "$target was not seen running"; }
  read -r stopped_step stopped_pid <"$scratch/stopped"
}

# 1. The sweep in an allocation of 2 CPUs; the Bagnold run at γ̇ = 100 (a few seconds: it must
#    not end between its first write and the stop) is killed with its job step. -k: make goes on with everything that does not need it.
copy_tree cluster && cd cluster && stamps
killed=runs/test/shear_nu0.700_e0.00_mu0.00_r1e+02_s1.h5
start_with_stop "$killed" ../cluster1.log salloc -n2 -c1 "${C[@]}" -k -j2 quick-files
scancel "$stopped_step"
rc=0
wait $make_pid || rc=$?
[ $rc -ne 0 ] || fail "the sweep succeeded although a job step was killed"
no_guard_refusal ../cluster1.log
grep -q "CANCELLED\|Killed\|Terminated" ../cluster1.log || fail "srun did not report the killed step"
[ ! -e "$killed" ] || fail "the killed run left $killed"
if "${M[@]}" "BIN=$scratch/bin" -q "$killed"; then fail "make trusts what the killed run left"; fi
after_kill=$(listing)
made=$(outputs | grep -v '/\.' || true)
[ -n "$made" ] || fail "nothing was made before the kill"
same_as_local $made
echo "slurm: the killed step left $(find runs -name '.*' -type f | wc -l) temporary file(s);" \
     "$(wc -l <<<"$made") of $(wc -l <<<"$local_files") outputs were made and match the local sweep"

# 2. The batch script finishes the sweep: only what was missing is made.
sbatch --wait -n2 -c1 -o ../sbatch.out pipelines/slurm/sweep.sbatch \
  SIZE=test STAMPS=stamps "GRANFLOW_BUILD=$build" PYTHON=/usr/bin/python3 "BIN=$scratch/bin" quick-files \
  >/dev/null || { no_guard_refusal ../sbatch.out; tail -n 20 ../sbatch.out >&2; fail "the batch job failed"; }
while read -r path size mtime; do
  [[ $(basename "$path") == .* ]] && continue
  [ -e "$path" ] && [ "$(find "$path" -printf '%s %T@')" = "$size $mtime" ] ||
    fail "$path was remade or removed by the second sweep"
done <<<"$after_kill"
[ "$(outputs)" = "$local_files" ] ||
  fail "the two sweeps made different files: $(diff <(outputs) <(echo "$local_files") | head)"
same_as_local $local_files
"${M[@]}" "BIN=$scratch/bin" -q quick-files || fail "make -q finds work after the sweep"
remade=$(comm -13 <(awk '{print $1}' <<<"$after_kill") <(echo "$local_files") | wc -l)
echo "slurm: the batch job made the $remade missing outputs; all $(wc -l <<<"$local_files") match the local sweep"

# 3. A time limit: Slurm sends SIGTERM to the step; gf-shear checkpoints, and the next sweep
#    resumes it. The resumed file has its own wall times (/run), so its trajectory and
#    parameters, not its bytes, are compared with the same run made locally. The run is made
#    500 times longer (SHEAR_STRAIN, 10⁵ steps, ≈ 2 s) so that the stop always falls inside
#    its step loop: the test size's 200 steps can end before a loaded machine stops them.
long=(SHEAR_STRAIN=100 SHEAR_FRAME_EVERY=1000)
resumed=runs/test/shear_nu0.700_e0.00_mu0.00_r1e-02_s1.h5
cd "$tree" && copy_tree reference3 && (cd reference3 && stamps && "${M[@]}" "BIN=$build/bin" "${long[@]}" "$resumed" \
  >../reference3.log 2>&1) || { tail ../reference3.log >&2; fail "the local long run failed"; }
cd cluster
rm "$resumed"
start_with_stop "$resumed" ../cluster3.log salloc -n1 -c1 "${C[@]}" "${long[@]}" "$resumed"
# What slurmstepd sends a step's processes at a time limit, sent here to the run itself, so
# that the test knows when the run sees it (through `scancel --signal=TERM` it does not).
kill -TERM "$stopped_pid"
kill -CONT "$stopped_pid"  # the pending SIGTERM is handled: a checkpoint, then exit 1
wait $make_pid && { tail -n 5 ../cluster3.log >&2; fail "a run stopped by SIGTERM was taken as finished"; }
[ -s "runs/test/.$(basename "$resumed").checkpoint" ] || fail "SIGTERM left no checkpoint of $resumed"
# (Not `make | grep -q`: grep's early exit would give make a SIGPIPE, which pipefail reports.)
plan=$("${M[@]}" "BIN=$scratch/bin" "${long[@]}" -n "$resumed")
grep -q -- "--resume" <<<"$plan" || fail "make does not pass --resume: $plan"
salloc -n1 -c1 "${C[@]}" "${long[@]}" "$resumed" >../cluster3b.log 2>&1 ||
  { tail ../cluster3b.log >&2; fail "the resumed run failed"; }
grep -q -- "gf-shear --quiet --resume .*-o $resumed" ../cluster3b.log || fail "$resumed was not resumed"
for group in /parameters /particles /observables /contacts; do
  h5diff -q "$resumed" "../reference3/$resumed" "$group" ||
    fail "the resumed $resumed differs from the local run in $group"
done
[ -z "$(find runs -name '.*')" ] || fail "temporary files left: $(find runs -name '.*')"
echo "slurm: a run stopped by SIGTERM resumed to the local trajectory"

# 4. LAUNCH ignored. Statically: every recipe calling a program starts with $(LAUNCH).
cd "$tree"
bad=$(grep -n '\$(BIN)/gf-' pipelines/*.mk | grep -v '\$(LAUNCH) \$(BIN)/gf-' | grep -v ':[0-9]*:#' || true)
[ -z "$bad" ] || fail "recipes that do not start with \$(LAUNCH):
$bad"
# Dynamically: a packing rule without $(LAUNCH) fails at the guard, and writes nothing.
copy_tree ignored && cd ignored && stamps
grep -q '\$(LAUNCH) \$(BIN)/gf-pack' pipelines/packings.mk || fail "the packing rule changed: update this test"
sed -i 's/\$(LAUNCH) \$(BIN)\/gf-pack/$(BIN)\/gf-pack/' pipelines/packings.mk
rc=0
salloc -n1 -c1 "${C[@]}" packings-files >../ignored.log 2>&1 || rc=$?
[ $rc -ne 0 ] || fail "a packing rule without \$(LAUNCH) went through"
grep -q "guard: gf-pack run outside a Slurm job step" ../ignored.log || fail "the guard did not stop gf-pack: $(tail -n 3 ../ignored.log)"
[ -z "$(find runs -type f 2>/dev/null)" ] || fail "files left by the refused sweep"
echo "slurm: a rule without \$(LAUNCH) is caught"

# 5. No Slurm: srun reports it (after its retries), make exits 2, and nothing is written.
slurm_down
cd "$tree" && copy_tree down && cd down && stamps
rc=0
"${M[@]}" "BIN=$build/bin" "LAUNCH=srun -n1 -c1" packings-files >../down.log 2>&1 || rc=$?
[ $rc -eq 2 ] || fail "make exited $rc with no Slurm running, not 2"
grep -q "Unable to contact slurm controller" ../down.log || fail "no clear line without Slurm: $(tail -n 3 ../down.log)"
[ -z "$(find runs -type f 2>/dev/null)" ] || fail "files written without Slurm: $(find runs -type f)"
echo "pipeline slurm: 5 passed, 0 failed"
