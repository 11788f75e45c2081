#!/usr/bin/env bash
# A real one-node SLURM on 127.0.0.1 for granstack's tests, without systemd or cgroups
# (../shared/slurm-local.md has the facts behind each setting). Never touches /etc/slurm: the
# configuration, state and logs live in $GRANSTACK_SLURM_DIR (default /tmp/granstack-slurm),
# and the SLURM commands find it through SLURM_CONF.
#
#   scripts/slurm-local.sh start   install slurm-wlm and munge if missing, start the cluster,
#                                  wait until its node is idle, print `export SLURM_CONF=...`
#   scripts/slurm-local.sh stop    cancel its jobs and stop what start started (by PID)
#   scripts/slurm-local.sh check   exit 0 when the cluster answers
set -euo pipefail
dir=${GRANSTACK_SLURM_DIR:-/tmp/granstack-slurm}
conf=$dir/slurm.conf
export SLURM_CONF=$conf
host=$(hostname -s)

say() { echo "slurm-local: $*" >&2; }

install_packages() {
  local missing=()
  for p in slurmctld slurmd slurm-client munge; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return
  [ "$(id -u)" -eq 0 ] || { say "run as root to install ${missing[*]}"; exit 1; }
  say "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

start_munge() {
  if munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then return; fi
  [ -f /etc/munge/munge.key ] || mungekey --create --keyfile=/etc/munge/munge.key
  chown munge: /etc/munge/munge.key
  chmod 0400 /etc/munge/munge.key
  mkdir -p /run/munge
  chown munge: /run/munge
  rm -f /run/munge/munge.socket.2 /run/munge/munge.socket.2.lock
  runuser -u munge -- /usr/sbin/munged
  cp /run/munge/munged.pid "$dir/munged.pid"  # ours: stop stops it
  for _ in $(seq 50); do munge -n 2>/dev/null | unmunge >/dev/null 2>&1 && return; sleep 0.1; done
  say "munged did not answer"
  exit 1
}

write_config() {
  local cpus mem
  cpus=$(nproc)
  mem=$(awk '/MemTotal/ { printf "%d", $2 / 1024 * 0.9 }' /proc/meminfo)
  mkdir -p "$dir/state" "$dir/spool" "$dir/log"
  cat > "$conf" <<CONF
# Written by granstack's scripts/slurm-local.sh: a one-node cluster on 127.0.0.1 for the tests.
ClusterName=granstack
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmctldPort=6917
SlurmdPort=6918
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SlurmdParameters=config_overrides
MpiDefault=none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
MailProg=/bin/true
ReturnToService=2
MinJobAge=600
EnforcePartLimits=ALL
SchedulerParameters=batch_sched_delay=0
NodeName=$host NodeAddr=127.0.0.1 NodeHostname=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
# Small enough that a test splits a sweep into several arrays for real.
MaxArraySize=4
PartitionName=granstack Nodes=$host Default=YES MaxTime=INFINITE State=UP
# A partition whose limit refuses a submission part-way (the arrays fit, a gather of 10 min not).
PartitionName=short Nodes=$host MaxTime=8 State=UP
CONF
}

node_state() { scontrol -o show node "$host" 2>/dev/null | grep -o 'State=[A-Z+_]*' | head -1 | cut -d= -f2; }

start() {
  install_packages
  mkdir -p "$dir"
  if [ -f "$dir/slurmctld.pid" ] && kill -0 "$(cat "$dir/slurmctld.pid")" 2>/dev/null; then
    say "already running ($dir)"
  else
    start_munge
    write_config
    slurmctld -c -f "$conf"
    slurmd -N "$host" -f "$conf"
  fi
  for _ in $(seq 150); do
    local line
    line=$(scontrol -o show node "$host" 2>/dev/null || true)
    case "$(node_state)" in
      IDLE|MIXED|ALLOCATED)
        if [[ $line == *SlurmdStartTime=2* ]]; then echo "export SLURM_CONF=$conf"; return; fi ;;
      *DOWN*|*DRAIN*) scontrol update nodename="$host" state=resume 2>/dev/null || true ;;
    esac
    sleep 0.2
  done
  say "the node did not become idle: $(scontrol -o show node "$host" 2>&1 | head -c 400)"
  say "logs: $dir/log"
  exit 1
}

stop_pid() {  # pidfile
  [ -f "$1" ] || return 0
  local pid
  pid=$(cat "$1")
  if kill -0 "$pid" 2>/dev/null; then
    kill -TERM "$pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null || true
  fi
  rm -f "$1"
}

stop() {
  [ -f "$conf" ] || { say "nothing to stop ($dir)"; return; }
  if [ -f "$dir/slurmctld.pid" ] && kill -0 "$(cat "$dir/slurmctld.pid")" 2>/dev/null; then
    # Cancel this cluster's jobs and let their slurmstepd end them; then whatever is left of
    # them (scontrol listpids: the PIDs of the jobs' processes on this node), by PID.
    scancel --partition=granstack 2>/dev/null || true
    for _ in $(seq 100); do [ -z "$(squeue -h 2>/dev/null)" ] && break; sleep 0.1; done
    for pid in $(scontrol listpids 2>/dev/null | awk 'NR > 1 { print $1 }'); do kill -KILL "$pid" 2>/dev/null || true; done
  fi
  stop_pid "$dir/slurmd.pid"
  stop_pid "$dir/slurmctld.pid"
  stop_pid "$dir/munged.pid"
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  check) [ "$(node_state)" != "" ] ;;
  *) echo "usage: $0 start|stop|check" >&2; exit 2 ;;
esac
