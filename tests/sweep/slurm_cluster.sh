# A single-node Slurm cluster for tests, from Debian's slurm-wlm and munge: munged with its own
# key and socket, slurmctld and slurmd as root from a private slurm.conf, everything (state,
# spool, logs, pid files) in one temporary folder, on private ports. Sourced by a test script:
#   . slurm_cluster.sh
#   slurm_cluster_start || { echo "SKIP: $SLURM_CLUSTER_WHY"; exit 77; }
#   trap slurm_cluster_stop EXIT        # kills the daemons, removes the folder, even on failure
# (and should the test be killed outright, a watchdog started with the cluster does the same)
# After a start, SLURM_CONF is exported (sbatch, squeue, sacct and scancel use it) and
# SLURM_CLUSTER_DIR is the folder; SLURM_CLUSTER_WHY says why a start failed.

SLURM_CLUSTER_DIR=""
SLURM_CLUSTER_WHY=""
SLURM_CLUSTER_PIDS=()

# a free TCP port on loopback, from a range unlikely to be used (bash's /dev/tcp probes it)
_slurm_free_port() {
  local p
  for p in $(shuf -i 20000-29999 -n 50); do
    (exec 3<>/dev/tcp/127.0.0.1/$p) 2>/dev/null || { echo "$p"; return 0; }
  done
  return 1
}

# waits up to $2 seconds until the command $1 succeeds
_slurm_wait_for() {
  local i
  for ((i = 0; i < $2 * 10; i++)); do
    eval "$1" >/dev/null 2>&1 && return 0
    sleep 0.1
  done
  return 1
}

slurm_cluster_start() {
  local p
  for p in munged slurmctld slurmd sbatch squeue sacct scancel scontrol; do
    command -v "$p" >/dev/null 2>&1 || [ -x "/usr/sbin/$p" ] || {
      SLURM_CLUSTER_WHY="'$p' is not installed (Debian packages slurm-wlm and munge)"; return 1; }
  done
  if [ "$(id -u)" -ne 0 ]; then
    SLURM_CLUSTER_WHY="slurmd must run as root to start jobs (this is uid $(id -u))"; return 1
  fi
  local d
  d="$(mktemp -d /tmp/ohrp_slurm.XXXXXX)" || { SLURM_CLUSTER_WHY="mktemp failed"; return 1; }
  SLURM_CLUSTER_DIR="$d"
  chmod 755 "$d"
  mkdir -p "$d/munge" "$d/state" "$d/spool" "$d/log"
  chmod 700 "$d/munge"
  # munge: a private key and socket (the machine's munged, if any, is left alone)
  dd if=/dev/urandom of="$d/munge/munge.key" bs=1024 count=1 status=none
  chmod 400 "$d/munge/munge.key"
  /usr/sbin/munged --key-file="$d/munge/munge.key" --socket="$d/munge/munge.socket" \
    --pid-file="$d/munge/munged.pid" --log-file="$d/log/munged.log" \
    --seed-file="$d/munge/munged.seed" --force >/dev/null 2>&1 || {
    SLURM_CLUSTER_WHY="munged did not start: $(tail -3 "$d/log/munged.log" 2>/dev/null)"; return 1; }
  _slurm_wait_for "test -s '$d/munge/munged.pid'" 10 || { SLURM_CLUSTER_WHY="munged wrote no pid file"; return 1; }
  SLURM_CLUSTER_PIDS+=("$(cat "$d/munge/munged.pid")")

  local ctl_port node_port host cpus mem
  ctl_port="$(_slurm_free_port)" && node_port="$(_slurm_free_port)" || {
    SLURM_CLUSTER_WHY="no free TCP port"; return 1; }
  host="$(hostname -s)"
  cpus="$(nproc)"
  mem=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2 ))
  cat > "$d/slurm.conf" <<CONF
ClusterName=ohrptest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctl_port
SlurmdPort=$node_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$d/munge/munge.socket
StateSaveLocation=$d/state
SlurmdSpoolDir=$d/spool/%n
SlurmctldPidFile=$d/slurmctld.pid
SlurmdPidFile=$d/slurmd.pid
SlurmctldLogFile=$d/log/slurmctld.log
SlurmdLogFile=$d/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
MinJobAge=300
MaxArraySize=${SLURM_MAX_ARRAY_SIZE:-1001}
KillWait=5
Waittime=0
PlugStackConfig=$d/plugstack.conf
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
  : > "$d/plugstack.conf"
  export SLURM_CONF="$d/slurm.conf"
  /usr/sbin/slurmctld -i -f "$d/slurm.conf" >"$d/log/slurmctld.out" 2>&1 || {
    SLURM_CLUSTER_WHY="slurmctld did not start: $(tail -3 "$d/log/slurmctld.log" "$d/log/slurmctld.out" 2>/dev/null)"; return 1; }
  _slurm_wait_for "test -s '$d/slurmctld.pid'" 10 && SLURM_CLUSTER_PIDS+=("$(cat "$d/slurmctld.pid")")
  /usr/sbin/slurmd -f "$d/slurm.conf" >"$d/log/slurmd.out" 2>&1 || {
    SLURM_CLUSTER_WHY="slurmd did not start: $(tail -3 "$d/log/slurmd.log" "$d/log/slurmd.out" 2>/dev/null)"; return 1; }
  _slurm_wait_for "test -s '$d/slurmd.pid'" 10 && SLURM_CLUSTER_PIDS+=("$(cat "$d/slurmd.pid")")
  # the node is up when the controller sees it idle
  if ! _slurm_wait_for "sinfo -h -N -o '%t' | grep -qx idle" 30; then
    SLURM_CLUSTER_WHY="the node never became idle: $(sinfo -N 2>&1 | tail -2); $(tail -3 "$d/log/slurmctld.log" 2>/dev/null)"
    return 1
  fi
  # a watchdog in its own session stops the cluster should the test die without its EXIT trap
  # (a ctest timeout kills the test's process tree with SIGKILL; the daemons are not in it)
  setsid -f bash -c '. "$1"; while kill -0 "$2" 2>/dev/null && [ -d "$3" ]; do sleep 1; done
                     [ -d "$3" ] && SLURM_CLUSTER_DIR="$3" slurm_cluster_stop' \
    _ "${BASH_SOURCE[0]}" "$$" "$d" </dev/null >/dev/null 2>&1
  return 0
}

slurm_cluster_stop() {
  local d="$SLURM_CLUSTER_DIR" pid
  [ -n "$d" ] || return 0
  # jobs still queued or running are cancelled first (their steps end with them)
  if [ -n "${SLURM_CONF:-}" ] && [ -s "$d/slurmctld.pid" ]; then
    local jobs
    jobs="$(squeue -h -o %A 2>/dev/null | sort -u | tr '\n' ' ')"
    if [ -n "$jobs" ]; then
      # shellcheck disable=SC2086
      scancel $jobs 2>/dev/null
      _slurm_wait_for "[ -z \"\$(squeue -h 2>/dev/null)\" ]" 15
    fi
  fi
  # the daemons this fixture started, by their pid files (never by name: another cluster may run)
  for f in "$d/slurmd.pid" "$d/slurmctld.pid" "$d/munge/munged.pid"; do
    [ -s "$f" ] && SLURM_CLUSTER_PIDS+=("$(cat "$f")")
  done
  for pid in "${SLURM_CLUSTER_PIDS[@]}"; do kill -TERM "$pid" 2>/dev/null; done
  for pid in "${SLURM_CLUSTER_PIDS[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null
  done
  # a job step left behind (slurmstepd outlives slurmd): those whose folder is this cluster's
  for pid in $(pgrep -x slurmstepd); do
    case "$(readlink "/proc/$pid/cwd" 2>/dev/null)" in "$d"/*|"$d") kill -KILL "$pid" 2>/dev/null ;; esac
  done
  rm -rf "$d"
  SLURM_CLUSTER_DIR=""
  SLURM_CLUSTER_PIDS=()
}
