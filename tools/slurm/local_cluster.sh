#!/usr/bin/env bash
# A throwaway single-node Slurm cluster on this machine, for testing deploy/slurm/ (issue 19).
#
#   tools/slurm/local_cluster.sh start    install slurm-wlm + munge if missing, write a private config,
#                                         start munged, slurmctld, slurmd, wait for the node to be idle
#   tools/slurm/local_cluster.sh stop     stop exactly the daemons `start` started (by pid file)
#   tools/slurm/local_cluster.sh status   which of them run, and what sinfo says
#   tools/slurm/local_cluster.sh env      print `export SLURM_CONF=…` for using sbatch/squeue by hand
#
# Everything lives in one private directory, $FB_SLURM_DIR (default /tmp/filterbench-slurm): config,
# munge key and socket, controller state, slurmd spool, logs and pid files. Nothing in /etc is written,
# no system service is touched, and a munged or Slurm the machine may already run is left alone: our
# munged has its own key and socket, and our daemons listen on their own ports ($FB_SLURM_PORT and the
# next one, default 6917/6918, away from Slurm's usual 6817/6818).
#
# Runs as root without systemd (Debian 12, slurm-wlm 22.05). tools/slurm/README.md records what was
# measured and why each setting is what it is. Every failure prints one line starting with
# "local_cluster:" and exits non-zero.
set -euo pipefail

DIR=${FB_SLURM_DIR:-/tmp/filterbench-slurm}
PORT=${FB_SLURM_PORT:-6917}
CONF=$DIR/etc/slurm.conf
MUNGE_SOCKET=$DIR/munge/munge.socket
READY_TIMEOUT=${FB_SLURM_READY_TIMEOUT:-90}

die() { echo "local_cluster: $*" >&2; exit 1; }
say() { echo "local_cluster: $*"; }

[ "$(id -u)" -eq 0 ] || die "must run as root (slurmd runs jobs as root here)"

# --- pid files: a daemon is "ours" only if its pid file names a live process running that program ---

pidfile() {
  case "$1" in
    munged) echo "$DIR/run/munged.pid" ;;
    slurmctld) echo "$DIR/run/slurmctld.pid" ;;
    slurmd) echo "$DIR/run/slurmd.pid" ;;
  esac
}

# Prints the pid if the pid file names a live process that is the daemon (Debian installs the Slurm
# ones as slurmctld-wlm and slurmd-wlm behind alternatives symlinks) started with our private
# directory on its command line. A stale pid file (process gone, or the pid reused by something else)
# prints nothing: we never signal a stranger.
live_pid() {
  local f pid exe
  f=$(pidfile "$1")
  [ -s "$f" ] || return 0
  pid=$(tr -dc '0-9' <"$f")
  [ -n "$pid" ] || return 0
  exe=$(readlink "/proc/$pid/exe" 2>/dev/null) || return 0
  case "$(basename "$exe")" in
    "$1" | "$1-wlm") ;;
    *) return 0 ;;
  esac
  tr '\0' '\n' <"/proc/$pid/cmdline" 2>/dev/null | grep -qF "$DIR/" && echo "$pid"
  return 0
}

# --- install ---

install_packages() {
  local need=() pkg
  for pkg in slurm-wlm slurmctld slurmd slurm-client munge; do
    dpkg -s "$pkg" >/dev/null 2>&1 || need+=("$pkg")
  done
  [ ${#need[@]} -eq 0 ] && return 0
  command -v apt-get >/dev/null || die "packages ${need[*]} missing and there is no apt-get to install them"
  say "installing ${need[*]} (apt)"
  # The packages' maintainer scripts would start munge and the Slurm daemons with the system's config.
  # Where the machine has no policy-rc.d forbidding that, put one in place for the install only, so
  # the only daemons that ever run are the ones this script starts from its own config.
  local policy=/usr/sbin/policy-rc.d made_policy=
  if [ ! -e "$policy" ]; then
    printf '#!/bin/sh\n# temporary, from filterbench tools/slurm/local_cluster.sh\nexit 101\n' >"$policy"
    chmod 755 "$policy"
    made_policy=1
  fi
  local rc=0 log=$DIR/log/apt.log
  mkdir -p "$DIR/log"
  {
    DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
      DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}"
  } >"$log" 2>&1 || rc=$?
  [ -z "$made_policy" ] || rm -f "$policy"
  [ $rc -eq 0 ] || die "apt-get install ${need[*]} failed (exit $rc): $(tail -n 1 "$log") (whole output: $log)"
}

# --- config ---

write_config() {
  local host node_line
  host=$(hostname -s) || die "hostname -s failed"
  [ -n "$host" ] || die "hostname -s printed nothing"
  # `slurmd -C` prints this machine's hardware as a NodeName line (CPUs, sockets, cores, threads,
  # RealMemory); we take it as it is so the node never registers with less than it was declared with
  # (which would drain it).
  node_line=$(slurmd -C 2>/dev/null | grep '^NodeName=') || die "slurmd -C printed no NodeName line"
  node_line=${node_line%% UpTime=*}
  [ "${node_line#NodeName="$host" }" != "$node_line" ] ||
    die "slurmd -C names the node '${node_line%% *}' but hostname -s is '$host'"

  mkdir -p "$DIR"/{etc,state,spool,log,run,munge}
  # munged insists that everyone can traverse to its socket (o+x), and that no one else can write there.
  chmod 711 "$DIR" "$DIR/munge"
  cat >"$CONF" <<EOF
# Written by tools/slurm/local_cluster.sh: a single-node test cluster. Do not edit; start rewrites it.
ClusterName=filterbench
# Pinned to loopback: the test cluster talks to nothing but this machine.
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$PORT
SlurmdPort=$((PORT + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
# Our own munged (own key, own socket), not the system's.
AuthInfo=socket=$MUNGE_SOCKET
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$(pidfile slurmctld)
SlurmdPidFile=$(pidfile slurmd)
SlurmctldLogFile=$DIR/log/slurmctld.log
SlurmdLogFile=$DIR/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# Process tracking by the parent-pid tree in /proc, and no task binding: neither needs cgroups or
# systemd, which this machine cannot give Slurm (cgroup.conf beside this file; why: local_cluster.sh).
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
# slurmd takes the node's hardware from this file rather than from what it detects.
SlurmdParameters=config_overrides
MpiDefault=none
# No accounting: no slurmdbd, no MySQL. (So no sacct: watch jobs with squeue.)
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
# Cores (not whole nodes) are the unit, so array tasks share the node.
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
# A node that was down (e.g. slurmd restarted) comes back by itself when it registers.
ReturnToService=2
# Short waits: this is a test cluster on one machine.
SlurmdTimeout=30
InactiveLimit=0
MinJobAge=60
KillWait=5
$node_line NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
  # cgroup.conf. Slurm 22.05's slurmd always loads a cgroup plugin at start-up, even with
  # proctrack/linuxproc, task/none and jobacct_gather/none, which then never create a cgroup (checked:
  # nothing appears under /sys/fs/cgroup/*/slurm*, and a job's /proc/self/cgroup is slurmd's own).
  # So the plugin has to be one that initialises on this machine:
  # - "disabled" does not exist before 23.02: slurmd 22.05 dies with "cannot find cgroup plugin for
  #   disabled".
  # - cgroup/v2 dies with "fatal: Hybrid mode is not supported": this machine mounts the v1
  #   controllers on a tmpfs at /sys/fs/cgroup and a v2 tree at /sys/fs/cgroup/unified, with no
  #   systemd to hand out a delegated v2 subtree.
  # - cgroup/v1 initialises (and is what the default "autodetect" picks on a tmpfs /sys/fs/cgroup).
  # We name it rather than rely on autodetect, so a change of layout fails with a clear message.
  # On a machine whose /sys/fs/cgroup is pure cgroup2 we take cgroup/v2 without systemd
  # (IgnoreSystemd): that branch is untested here.
  local fstype plugin
  fstype=$(stat -fc %T /sys/fs/cgroup 2>/dev/null) || die "cannot stat /sys/fs/cgroup (is it mounted?)"
  case "$fstype" in
    tmpfs) plugin="CgroupPlugin=cgroup/v1" ;;
    cgroup2fs) plugin=$'CgroupPlugin=cgroup/v2\nIgnoreSystemd=yes' ;;
    *) die "/sys/fs/cgroup is a '$fstype' file system; Slurm 22.05 needs tmpfs (cgroup v1) or cgroup2fs" ;;
  esac
  cat >"$DIR/etc/cgroup.conf" <<EOF
# Written by tools/slurm/local_cluster.sh (see the comment there): /sys/fs/cgroup is $fstype.
$plugin
CgroupAutomount=no
EOF
}

# --- daemons ---

start_munged() {
  local key=$DIR/munge/munge.key
  if [ ! -s "$key" ]; then
    if command -v mungekey >/dev/null; then
      mungekey --create --keyfile="$key" >/dev/null 2>&1 || die "mungekey could not create $key"
    else
      dd if=/dev/urandom of="$key" bs=1 count=1024 status=none || die "could not create $key"
    fi
  fi
  chmod 400 "$key"
  rm -f "$MUNGE_SOCKET" "$MUNGE_SOCKET.lock"
  munged --key-file="$key" --socket="$MUNGE_SOCKET" --pid-file="$(pidfile munged)" \
    --log-file="$DIR/log/munged.log" --seed-file="$DIR/munge/munged.seed" ||
    die "munged did not start (see $DIR/log/munged.log)"
  local i
  for i in $(seq 50); do
    if munge -n -S "$MUNGE_SOCKET" 2>/dev/null | unmunge -S "$MUNGE_SOCKET" >/dev/null 2>&1; then
      return 0
    fi
    sleep 0.1
  done
  die "munged started but a credential does not round-trip through $MUNGE_SOCKET"
}

# Starts a Slurm daemon and waits for its pid file to name it.
start_slurm_daemon() {
  local name=$1 i
  SLURM_CONF=$CONF "$name" -f "$CONF" >>"$DIR/log/$name.start" 2>&1 ||
    die "$name did not start (see $DIR/log/$name.log and $DIR/log/$name.start)"
  for i in $(seq 100); do
    [ -n "$(live_pid "$name")" ] && return 0
    sleep 0.1
  done
  die "$name exited right after starting (last log line: $(tail -n 1 "$DIR/log/$name.log" 2>/dev/null))"
}

node_state() {
  SLURM_CONF=$CONF sinfo -h -N -o '%T' 2>/dev/null | head -n 1
}

wait_idle() {
  local i d state=
  for i in $(seq "$READY_TIMEOUT"); do
    state=$(node_state) || true
    case "$state" in
      idle) return 0 ;;
      # The node was declared with more than it has, or slurmd failed a check: no point waiting.
      drain* | fail*)
        die "node is '$state': $(SLURM_CONF=$CONF sinfo -h -N -o '%E' 2>/dev/null | head -n 1)" ;;
    esac
    for d in slurmctld slurmd; do
      [ -n "$(live_pid "$d")" ] || die "$d died while the node was coming up (last log line: $(tail -n 1 "$DIR/log/$d.log" 2>/dev/null))"
    done
    sleep 1
  done
  die "node not idle after ${READY_TIMEOUT}s (sinfo says '${state:-nothing}')"
}

stop_one() {
  local name=$1 pid i
  pid=$(live_pid "$name")
  if [ -z "$pid" ]; then
    rm -f "$(pidfile "$name")"
    return 0
  fi
  kill -TERM "$pid" 2>/dev/null || true
  for i in $(seq 100); do
    kill -0 "$pid" 2>/dev/null || {
      rm -f "$(pidfile "$name")"
      say "stopped $name ($pid) in $(awk -v i="$i" 'BEGIN { printf "%.1f", (i - 1) / 10 }')s"
      return 0
    }
    sleep 0.1
  done
  kill -KILL "$pid" 2>/dev/null || true
  sleep 0.2
  kill -0 "$pid" 2>/dev/null && die "$name ($pid) survived SIGKILL"
  rm -f "$(pidfile "$name")"
  say "killed $name ($pid): it ignored SIGTERM for 10s"
}

# Running jobs outlive slurmd by design (a slurmstepd runs each one and a restarted slurmd takes them
# back), so a stop that only stopped the daemons would leave jobs running. While the controller is
# up, cancel every job of this private cluster and give them a few seconds to end.
cancel_jobs() {
  [ -n "$(live_pid slurmctld)" ] || return 0
  local ids i
  ids=$(SLURM_CONF=$CONF squeue -h -o '%A' 2>/dev/null) || return 0
  [ -n "$ids" ] || return 0
  # shellcheck disable=SC2086
  SLURM_CONF=$CONF scancel $ids 2>/dev/null || true
  for i in $(seq 50); do
    [ -z "$(SLURM_CONF=$CONF squeue -h -o '%A' 2>/dev/null)" ] && break
    sleep 0.2
  done
  say "cancelled job(s) $(echo "$ids" | tr '\n' ',' | sed 's/,$//')"
}

kill_tree() {
  local child
  for child in $(ps -o pid= --ppid "$1" 2>/dev/null); do kill_tree "$child"; done
  kill -KILL "$1" 2>/dev/null || true
}

# What a hard-killed slurmd leaves: slurmstepds (which ignore SIGTERM) and their jobs. Ours are the
# ones whose environment names our slurm.conf (the daemons are started with SLURM_CONF set).
stop_stray_stepds() {
  local pid
  for pid in $(pgrep -x slurmstepd 2>/dev/null || true); do
    if tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -qx "SLURM_CONF=$CONF"; then
      kill_tree "$pid"
      say "killed stray slurmstepd ($pid) and its processes"
    fi
  done
}

all_running() {
  [ -n "$(live_pid munged)" ] && [ -n "$(live_pid slurmctld)" ] && [ -n "$(live_pid slurmd)" ]
}

cmd_stop() {
  cancel_jobs
  # Reverse order: slurmd first so it does not spend its last seconds retrying a dead controller.
  stop_one slurmd
  stop_one slurmctld
  stop_stray_stepds
  stop_one munged
  return 0
}

cmd_start() {
  if all_running && [ "$(node_state)" = idle ]; then
    say "already running (node idle); $0 stop first for a fresh start"
    return 0
  fi
  # Whatever a previous, interrupted run left running (by our pid files only) goes first; then the
  # controller's saved state and slurmd's spool are cleared, so jobs of a killed run are not replayed.
  cmd_stop
  install_packages
  # A start that fails half-way stops what it had started: it leaves nothing running.
  trap 'cmd_stop >/dev/null 2>&1' EXIT
  local t0=$SECONDS
  write_config
  rm -rf "${DIR:?}"/state/* "${DIR:?}"/spool/*
  : >"$DIR/log/slurmctld.log"
  : >"$DIR/log/slurmd.log"
  : >"$DIR/log/munged.log"
  start_munged
  start_slurm_daemon slurmctld
  start_slurm_daemon slurmd
  wait_idle
  trap - EXIT
  say "up in $((SECONDS - t0))s: $(SLURM_CONF=$CONF sinfo -h -N -o '%N %T cpus=%c mem=%mMB') (SLURM_CONF=$CONF)"
}

cmd_status() {
  local d pid rc=0
  for d in munged slurmctld slurmd; do
    pid=$(live_pid "$d")
    if [ -n "$pid" ]; then say "$d running ($pid)"; else say "$d not running"; rc=3; fi
  done
  if [ $rc -eq 0 ]; then
    say "node: $(SLURM_CONF=$CONF sinfo -h -N -o '%N %T cpus=%c mem=%mMB' 2>&1 | head -n 1)"
  fi
  return $rc
}

case "${1:-}" in
  start) cmd_start ;;
  stop) cmd_stop ;;
  status) cmd_status ;;
  env) echo "export SLURM_CONF=$CONF" ;;
  *) die "usage: $0 start|stop|status|env" ;;
esac
