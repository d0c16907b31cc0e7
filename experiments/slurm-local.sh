#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, in one folder, for trying experiments/slurm-array.sh
# on a laptop (and for its test, cli/tests/integration/slurm_array.rs).
#
#   experiments/slurm-local.sh start DIR   # prints: export SLURM_CONF=DIR/slurm.conf
#   experiments/slurm-local.sh stop DIR    # cancels its jobs, stops its daemons
#
# Needs Debian's slurm-wlm and munge (`apt-get install slurm-wlm munge`). Run it as root or as
# yourself: the daemons run as the user who starts them, and so do the jobs. `start` writes a
# minimal slurm.conf (one node named after `hostname -s`, free ports, proctrack/linuxproc,
# task/none, select/cons_tres), a munge key and socket, and the state, spool and log folders,
# all inside DIR; then starts munged, slurmctld and slurmd by hand (no systemd) and waits until
# the node is idle. `stop` stops only the processes whose PIDs `start` recorded in DIR/pids.
# Nothing outside DIR is written, so it runs beside a system Slurm and beside other local
# clusters. Daemon logs: DIR/log/.
set -euo pipefail

usage() {
  echo "usage: $0 start|stop DIR" >&2
  exit 2
}
[ $# -eq 2 ] || usage
CMD="$1"
mkdir -p "$2"
DIR="$(cd "$2" && pwd)"
export SLURM_CONF="$DIR/slurm.conf"
HOST="$(hostname -s)"
# Debian puts the daemons in /usr/sbin, which a user's PATH may lack.
PATH="$PATH:/usr/sbin:/sbin"
DEADLINE_S="${SLURM_LOCAL_DEADLINE_S:-60}"

# Waits until the command "$@" succeeds, polling, for at most DEADLINE_S seconds.
wait_for() {
  local what="$1"
  shift
  local end=$((SECONDS + DEADLINE_S))
  until "$@" >/dev/null 2>&1; do
    local pid
    for pid in $(tac "$DIR/pids" 2>/dev/null); do
      if ! alive "$pid"; then
        echo "slurm-local: $what: a daemon exited (logs in $DIR/log)" >&2
        return 1
      fi
    done
    if [ "$SECONDS" -ge "$end" ]; then
      echo "slurm-local: $what: not within ${DEADLINE_S} s (logs in $DIR/log)" >&2
      return 1
    fi
    sleep 0.2
  done
}

# True while PID runs (a zombie does not). Just after a start, its command line may still be
# this script's: the child has not yet executed the daemon.
alive() {
  local state
  state="$(cut -d' ' -f3 2>/dev/null <"/proc/$1/stat")" && [ -n "$state" ] && [ "$state" != Z ]
}

# True while PID is alive and is one of the daemons started for DIR (guards against PID reuse).
ours() { tr '\0' ' ' 2>/dev/null <"/proc/$1/cmdline" | grep -qF "$DIR/"; }

# A TCP port that nothing listens on (from /proc/net/tcp*), between 20000 and 59999.
free_port() {
  local used p
  used="$(cat /proc/net/tcp /proc/net/tcp6 2>/dev/null | awk 'NR > 1 { split($2, a, ":"); print a[2] }')"
  for _ in $(seq 200); do
    p=$((20000 + RANDOM % 40000))
    if ! grep -qi "^$(printf '%04X' "$p")$" <<<"$used"; then
      echo "$p"
      return
    fi
  done
  echo "slurm-local: no free port found" >&2
  return 1
}

node_idle() { [ "$(sinfo -h -n "$HOST" -o %T)" = idle ]; }
# No job in the queue and no job step left on the node (slurmd keeps a socket per step).
no_jobs() { [ -z "$(squeue -h -o %A)" ] && ! compgen -G "$DIR/spool/${HOST}_*" >/dev/null; }

stop() {
  [ -f "$DIR/pids" ] || return 0
  if [ -f "$SLURM_CONF" ] && scontrol ping >/dev/null 2>&1; then
    # Cancel this cluster's jobs and let their slurmstepd processes end (they outlive slurmd).
    squeue -h -o %A | xargs -r scancel || true
    wait_for "jobs ending" no_jobs || true
  fi
  local pid
  # slurmd, slurmctld, then munged: the reverse of the start order.
  for pid in $(tac "$DIR/pids"); do
    if ours "$pid"; then kill "$pid" 2>/dev/null || true; fi
  done
  for pid in $(tac "$DIR/pids"); do
    local end=$((SECONDS + 20))
    while ours "$pid" && [ "$SECONDS" -lt "$end" ]; do sleep 0.1; done
    if ours "$pid"; then kill -9 "$pid" 2>/dev/null || true; fi
  done
  rm -f "$DIR/pids"
}

# Starts "$@" in the background in its own session, logging to DIR/log/NAME.out, and records
# its PID.
daemon() {
  local name="$1"
  shift
  setsid "$@" >>"$DIR/log/$name.out" 2>&1 </dev/null &
  echo $! >>"$DIR/pids"
}

start() {
  for c in munged mungekey slurmctld slurmd sbatch; do
    command -v "$c" >/dev/null || {
      echo "slurm-local: $c not found: apt-get install slurm-wlm munge" >&2
      exit 1
    }
  done
  [ ! -f "$DIR/pids" ] || {
    echo "slurm-local: $DIR already runs a cluster (stop it first)" >&2
    exit 1
  }
  local user ctld_port slurmd_port node
  user="$(id -un)"
  ctld_port="$(free_port)"
  slurmd_port="$(free_port)"
  while [ "$slurmd_port" = "$ctld_port" ]; do slurmd_port="$(free_port)"; done
  # The node as slurmd sees it (CPUs, sockets, cores, threads, memory).
  node="$(slurmd -C | head -n1 | sed 's/^NodeName=[^ ]* //')"
  # munged wants its key private, and its socket's folder and every folder above it open to
  # all users (search permission: a 0700 temporary folder is not enough).
  chmod a+x "$DIR"
  mkdir -p "$DIR/munge" "$DIR/socket" "$DIR/state" "$DIR/spool" "$DIR/log"
  chmod 700 "$DIR/munge"
  chmod 755 "$DIR/socket"
  rm -f "$DIR/munge/munge.key"
  mungekey --create --keyfile="$DIR/munge/munge.key"
  chmod 600 "$DIR/munge/munge.key"
  cat >"$SLURM_CONF" <<EOF
# One-node cluster written by experiments/slurm-local.sh; everything lives in $DIR.
ClusterName=magbench-local
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$DIR/socket/munge.socket
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/slurmctld.pid
SlurmdPidFile=$DIR/slurmd.pid
SlurmctldLogFile=$DIR/log/slurmctld.log
SlurmdLogFile=$DIR/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
# Start a pending job as soon as a CPU frees: no batching delay, the backfill pass every second
# (defaults: 3 s and 30 s), so an array of short tasks is not paced by the scheduler.
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0,bf_interval=1
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
KillWait=5
NodeName=$HOST NodeAddr=127.0.0.1 $node State=UNKNOWN
PartitionName=local Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
  : >"$DIR/pids"
  trap 'echo "slurm-local: start failed; stopping what started (logs in $DIR/log)" >&2; stop' ERR
  daemon munged munged -F --key-file="$DIR/munge/munge.key" --socket="$DIR/socket/munge.socket" \
    --pid-file="$DIR/munge/munged.pid" --log-file="$DIR/log/munged.log" \
    --seed-file="$DIR/munge/munged.seed"
  wait_for "munged" munge -n -S "$DIR/socket/munge.socket"
  daemon slurmctld slurmctld -D -c -f "$SLURM_CONF"
  wait_for "slurmctld" scontrol ping
  daemon slurmd slurmd -D -f "$SLURM_CONF" -N "$HOST"
  wait_for "node $HOST idle" node_idle
  trap - ERR
  echo "export SLURM_CONF=$SLURM_CONF"
}

case "$CMD" in
start) start ;;
stop) stop ;;
*) usage ;;
esac
