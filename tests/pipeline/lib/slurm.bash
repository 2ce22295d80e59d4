# Sourced by the tests that need a real Slurm: slurm_up DIR brings up munged, slurmctld and
# slurmd from Debian's packages (slurm-wlm, munge) in the scratch directory DIR, with this
# machine as the only node and every daemon file (key, socket, state, logs) under DIR;
# slurm_down stops them, whatever state they are in. DIR's parents must be searchable by all
# (munged refuses a socket under a private directory). Exports SLURM_CONF, so that salloc,
# srun, sbatch and scontrol find this cluster and no other.
#
# Why these settings: proctrack/linuxproc and task/none need neither systemd nor cgroups;
# the munge socket is named in AuthInfo because there is no /run/munge here; the ports are
# chosen free per run so that two tests, or a system Slurm, never meet; every wait is
# bounded, because srun and sinfo retry for about 10 s against a controller that is down; no
# daemon keeps the caller's stdout open (ctest would wait for it). Callers must not use a bare
# `wait`: slurmctld and slurmd are background jobs of the calling shell.

slurm_fail() { echo "FAIL: $*" >&2; return 1; }

slurm_up() {
  local d=$1 exe
  for exe in munged mungekey slurmctld slurmd salloc srun sbatch scontrol sinfo; do
    command -v "$exe" >/dev/null ||
      slurm_fail "$exe not found: install the Debian packages slurm-wlm and munge (make -f Makefile.sweeps deps-test)" ||
      return 1
  done
  mkdir -p "$d"/munge "$d"/state "$d"/spool "$d"/log "$d"/run
  # munged refuses a socket directory that others cannot traverse.
  chmod 755 "$d" "$d"/munge
  local user host ports
  user=$(id -un)
  host=$(hostname -s)
  ports=$(python3 -c 'import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(" ".join(str(x.getsockname()[1]) for x in s))')
  read -r SLURM_CTLD_PORT SLURM_D_PORT <<<"$ports"
  cat >"$d"/slurm.conf <<CONF
ClusterName=granflowtest
SlurmctldHost=$host(127.0.0.1)
SlurmUser=$user
SlurmdUser=$user
SlurmctldPort=$SLURM_CTLD_PORT
SlurmdPort=$SLURM_D_PORT
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$d/munge/socket
MpiDefault=none
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
KillWait=5
StateSaveLocation=$d/state
SlurmdSpoolDir=$d/spool
SlurmctldPidFile=$d/run/slurmctld.pid
SlurmdPidFile=$d/run/slurmd.pid
SlurmctldLogFile=$d/log/slurmctld.log
SlurmdLogFile=$d/log/slurmd.log
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=granflow Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
  chmod 644 "$d"/slurm.conf
  export SLURM_CONF=$d/slurm.conf
  SLURM_DIR=$d
  mungekey -c -k "$d"/munge/munge.key || slurm_fail "mungekey could not make a key" || return 1
  munged --socket="$d"/munge/socket --key-file="$d"/munge/munge.key --pid-file="$d"/munge/munged.pid \
    --log-file="$d"/munge/munged.log --seed-file="$d"/munge/munged.seed >"$d"/log/munged.out 2>&1 </dev/null ||
    slurm_fail "munged did not start (log: $(tail -n 3 "$d"/munge/munged.log 2>/dev/null))" || return 1
  setsid slurmctld -D -c -f "$SLURM_CONF" >"$d"/log/slurmctld.out 2>&1 </dev/null &
  SLURM_CTLD_PID=$!
  setsid slurmd -D -f "$SLURM_CONF" >"$d"/log/slurmd.out 2>&1 </dev/null &
  SLURM_D_PID=$!
  local i state=
  for i in $(seq 150); do
    state=$(timeout 5 sinfo -h -o %t 2>/dev/null || true)
    [ "$state" = idle ] && return 0
    kill -0 "$SLURM_CTLD_PID" 2>/dev/null && kill -0 "$SLURM_D_PID" 2>/dev/null || break
    sleep 0.2
  done
  slurm_fail "the Slurm node is not idle (state '$state'); logs:
$(tail -n 5 "$d"/log/slurmctld.log "$d"/log/slurmd.log "$d"/log/*.out 2>/dev/null)"
}

# Stops the daemons slurm_up started; safe to call twice or after a failed start.
slurm_down() {
  [ -n "${SLURM_DIR:-}" ] || return 0
  local pid i
  timeout 10 scontrol shutdown >/dev/null 2>&1 || true
  for pid in ${SLURM_CTLD_PID:-} ${SLURM_D_PID:-}; do
    for i in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
    kill -9 "$pid" 2>/dev/null || true
  done
  if [ -S "$SLURM_DIR"/munge/socket ]; then
    timeout 10 munged --stop --socket="$SLURM_DIR"/munge/socket >/dev/null 2>&1 || true
  fi
  pid=$(cat "$SLURM_DIR"/munge/munged.pid 2>/dev/null || true)
  [ -n "$pid" ] && kill -9 "$pid" 2>/dev/null || true
  SLURM_DIR=
}
