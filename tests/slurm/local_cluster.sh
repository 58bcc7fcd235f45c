#!/usr/bin/env bash
# A private single-node Slurm cluster on localhost for the tests: munged with its own key and socket, slurmctld
# and slurmd with a slurm.conf generated from tests/slurm/slurm.conf.in on two free ports, all state, spool, pid
# and log files under one directory. Nothing outside that directory is read or changed (no /etc/slurm, no
# /run/munge), so it coexists with a system Slurm and with other test clusters.
#
# As a library (what the tests do):
#   source tests/slurm/local_cluster.sh
#   cluster_start "$dir" || { echo "SKIPPED: $CLUSTER_ERROR"; exit 77; }   # exports SLURM_CONF
#   trap 'cluster_stop "$dir"' EXIT
# As a command, to try scripts/slurm by hand:
#   bash tests/slurm/local_cluster.sh start DIR    # then: source DIR/env.sh (sets SLURM_CONF)
#   bash tests/slurm/local_cluster.sh stop DIR
# Needs root (slurmd starts each job as its submitting user) and the Debian packages munge, slurmctld, slurmd
# and slurm-client. Works in containers without systemd or cgroup delegation (Slurm 22.05, Debian 12).

CLUSTER_TEMPLATE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/slurm.conf.in"
CLUSTER_NODE="madsfm-node"
CLUSTER_ERROR=""

# Whether this machine can run the cluster at all; the reason goes to CLUSTER_ERROR.
cluster_check_prerequisites() {
  if [[ "${MADSFM_SKIP_SLURM:-0}" == 1 ]]; then
    CLUSTER_ERROR="MADSFM_SKIP_SLURM=1"
    return 1
  fi
  if [[ "$(id -u)" != 0 ]]; then
    CLUSTER_ERROR="not running as root (slurmd must be root to start jobs as their user)"
    return 1
  fi
  local cmd missing=()
  for cmd in munged munge unmunge slurmctld slurmd sbatch scontrol sinfo squeue scancel; do
    command -v "$cmd" >/dev/null 2>&1 || missing+=("$cmd")
  done
  if ((${#missing[@]} > 0)); then
    CLUSTER_ERROR="${missing[*]} not found (Debian packages: munge slurmctld slurmd slurm-client)"
    return 1
  fi
  [[ -r "$CLUSTER_TEMPLATE" ]] || {
    CLUSTER_ERROR="$CLUSTER_TEMPLATE is missing"
    return 1
  }
}

# Nothing accepts connections on 127.0.0.1:PORT.
cluster_port_free() {
  ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null
}

# Two adjacent free ports, random so that concurrent test clusters rarely collide; sets CLUSTER_PORT.
cluster_pick_ports() {
  local try port
  for ((try = 0; try < 50; try++)); do
    port=$((20000 + (RANDOM * 32768 + RANDOM + $$) % 40000))
    if cluster_port_free "$port" && cluster_port_free "$((port + 1))"; then
      CLUSTER_PORT="$port"
      return 0
    fi
  done
  CLUSTER_ERROR="no two free TCP ports on 127.0.0.1 found"
  return 1
}

# PID is alive (not a zombie) and was started with a path inside DIR on its command line: a pid file left
# behind never makes us signal an unrelated process that reuses the number.
cluster_pid_is_ours() {
  local dir="$1" pid="$2" state
  [[ "$pid" =~ ^[0-9]+$ && -r "/proc/$pid/stat" ]] || return 1
  state="$(sed 's/.*) //' "/proc/$pid/stat" 2>/dev/null | cut -d' ' -f1)"
  [[ -n "$state" && "$state" != Z ]] || return 1
  tr '\0' ' ' 2>/dev/null <"/proc/$pid/cmdline" | grep -qF -- "$dir/"
}

# Starts a daemon in the foreground mode of its own, in the background of this shell, and records its pid.
# stdin/stdout/stderr go to files: a daemon holding the caller's pipes would keep ctest waiting.
cluster_spawn() {
  local dir="$1" name="$2"
  shift 2
  "$@" </dev/null >>"$dir/log/$name.out" 2>&1 &
  echo "$!" >"$dir/pids/$name"
}

cluster_daemon_alive() {
  local dir="$1" name="$2"
  [[ -f "$dir/pids/$name" ]] && cluster_pid_is_ours "$dir" "$(<"$dir/pids/$name")"
}

# The last lines of a daemon's log file, or of its captured output when it wrote no log (munged in the
# foreground, errors before logging started).
cluster_log_tail() {
  local dir="$1" name="$2"
  if [[ -s "$dir/log/$name.log" ]]; then
    tail -n 5 "$dir/log/$name.log"
  elif [[ -s "$dir/log/$name.out" ]]; then
    tail -n 5 "$dir/log/$name.out"
  fi
  return 0
}

# Polls CONDITION (a command) every 0.2 s for up to SECONDS until it holds; fails early when one of the
# daemons started so far dies, naming it. WHAT names the awaited state in the timeout message.
cluster_wait_until() {
  local dir="$1" seconds="$2" what="$3" i f name
  shift 3
  for ((i = 0; i < seconds * 5; i++)); do
    "$@" && return 0
    for f in "$dir"/pids/*; do
      name="$(basename "$f")"
      if ! cluster_daemon_alive "$dir" "$name"; then
        CLUSTER_ERROR="$name exited during start-up: $(cluster_log_tail "$dir" "$name")"
        return 1
      fi
    done
    sleep 0.2
  done
  CLUSTER_ERROR="$what not within $seconds s: $(cluster_log_tail "$dir" slurmctld) $(cluster_log_tail "$dir" slurmd)"
  return 1
}

cluster_munge_works() {
  munge -n --socket="$1/munge/munge.socket" 2>/dev/null | unmunge --socket="$1/munge/munge.socket" >/dev/null 2>&1
}

cluster_node_idle() {
  [[ "$(sinfo -h -n "$CLUSTER_NODE" -o %T 2>/dev/null)" == idle ]]
}

cluster_write_config() {
  local dir="$1" host
  host="$(uname -n)"
  host="${host%%.*}"
  sed -e "s|@DIR@|$dir|g" -e "s|@HOST@|$host|g" -e "s|@NODE@|$CLUSTER_NODE|g" -e "s|@CPUS@|$(nproc)|g" \
    -e "s|@CTLD_PORT@|$CLUSTER_PORT|g" -e "s|@SLURMD_PORT@|$((CLUSTER_PORT + 1))|g" \
    "$CLUSTER_TEMPLATE" >"$dir/slurm.conf"
  : >"$dir/plugstack.conf"
  echo "export SLURM_CONF='$dir/slurm.conf'" >"$dir/env.sh"
}

# Starts munged, slurmctld and slurmd under DIR and waits (up to TIMEOUT s, default 60) for the node to be
# idle. Exports SLURM_CONF for the client commands. On failure everything started is stopped again,
# CLUSTER_ERROR says why, and the status is 1.
cluster_start() {
  local dir="$1" timeout="${2:-60}"
  CLUSTER_ERROR=""
  cluster_check_prerequisites || return 1
  if ! mkdir -p "$dir"; then
    CLUSTER_ERROR="cannot create $dir"
    return 1
  fi
  dir="$(cd "$dir" && pwd)"
  mkdir -p "$dir"/{munge,state,spool,log,run,pids}
  cluster_pick_ports || return 1

  # munged checks that its key is private and its socket folder reachable.
  (umask 077 && dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none)
  chmod 755 "$dir/munge"
  # --force: munged refuses to run as root without it.
  cluster_spawn "$dir" munged munged --foreground --force --socket="$dir/munge/munge.socket" \
    --key-file="$dir/munge/munge.key" --pid-file="$dir/run/munged.pid" --log-file="$dir/log/munged.log" \
    --seed-file="$dir/munge/munged.seed"
  if ! cluster_wait_until "$dir" 10 "munged answering" cluster_munge_works "$dir"; then
    cluster_stop "$dir"
    return 1
  fi

  cluster_write_config "$dir"
  export SLURM_CONF="$dir/slurm.conf"
  # -D keeps the daemons in this process tree (so cluster_stop can reap them); -i tolerates the empty state.
  cluster_spawn "$dir" slurmctld slurmctld -D -i -f "$SLURM_CONF"
  cluster_spawn "$dir" slurmd slurmd -D -f "$SLURM_CONF" -N "$CLUSTER_NODE"
  if ! cluster_wait_until "$dir" "$timeout" "node $CLUSTER_NODE idle" cluster_node_idle; then
    cluster_stop "$dir"
    return 1
  fi
}

# TERM, up to 10 s of grace, then KILL; reaps the daemon when this shell started it.
cluster_kill() {
  local dir="$1" name="$2" pid i
  [[ -f "$dir/pids/$name" ]] || return 0
  pid="$(<"$dir/pids/$name")"
  if cluster_pid_is_ours "$dir" "$pid"; then
    kill -TERM "$pid" 2>/dev/null || true
    for ((i = 0; i < 50; i++)); do
      cluster_pid_is_ours "$dir" "$pid" || break
      sleep 0.2
    done
    if cluster_pid_is_ours "$dir" "$pid"; then kill -KILL "$pid" 2>/dev/null || true; fi
  fi
  wait "$pid" 2>/dev/null || true
  rm -f "$dir/pids/$name"
}

# Cancels the cluster's jobs (their slurmstepd processes outlive slurmd by design), then stops slurmd,
# slurmctld and munged. Safe to call twice, and on a half-started cluster.
cluster_stop() {
  local dir="$1" i jobs
  [[ -d "$dir/pids" ]] || return 0
  if cluster_daemon_alive "$dir" slurmctld; then
    jobs="$(SLURM_CONF="$dir/slurm.conf" squeue -h -o %F 2>/dev/null | sort -u | tr '\n' ' ')"
    if [[ -n "${jobs// /}" ]]; then
      # shellcheck disable=SC2086  # one argument per job id
      SLURM_CONF="$dir/slurm.conf" scancel $jobs 2>/dev/null || true
      for ((i = 0; i < 50; i++)); do
        [[ -z "$(SLURM_CONF="$dir/slurm.conf" squeue -h 2>/dev/null)" ]] && break
        sleep 0.2
      done
    fi
  fi
  cluster_kill "$dir" slurmd
  cluster_kill "$dir" slurmctld
  cluster_kill "$dir" munged
  return 0
}

# The daemons' logs, for a failing test's output. A daemon's captured output (.out) repeats its log file, so it
# is shown only when the log file stayed empty (an error before logging started).
cluster_print_logs() {
  local dir="$1" f
  for f in "$dir"/log/*; do
    [[ -s "$f" ]] || continue
    [[ "$f" != *.out || ! -s "${f%.out}.log" ]] || continue
    echo "---- $f (last 30 lines)"
    tail -n 30 "$f"
  done
}

# The JobState of a job, one line per array task.
cluster_job_states() {
  scontrol -o show job "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | cut -d= -f2
}

# Waits up to SECONDS for every task of job ID to end; fails on timeout. A job whose dependency can never be
# satisfied counts as ended (it would wait forever).
cluster_wait_job() {
  local id="$1" seconds="$2" i state states done_
  for ((i = 0; i < seconds * 2; i++)); do
    states="$(cluster_job_states "$id")"
    if [[ -n "$states" ]]; then
      done_=1
      for state in $states; do
        case "$state" in
          COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | PREEMPTED | BOOT_FAIL | DEADLINE | OUT_OF_MEMORY) ;;
          *) done_=0 ;;
        esac
      done
      ((done_)) && return 0
      scontrol -o show job "$id" 2>/dev/null | grep -q 'Reason=DependencyNeverSatisfied' && return 0
    fi
    sleep 0.5
  done
  return 1
}

if [[ "${BASH_SOURCE[0]}" == "$0" ]]; then
  set -euo pipefail
  case "${1:-}:${2:-}" in
    start:?*)
      cluster_start "$2" || {
        echo "local_cluster.sh: cannot start the cluster: $CLUSTER_ERROR" >&2
        exit 1
      }
      echo "cluster up in $2 (port $CLUSTER_PORT); use it with: source $2/env.sh"
      ;;
    stop:?*) cluster_stop "$(cd "$2" && pwd)" ;;
    *)
      echo "usage: local_cluster.sh start|stop DIR" >&2
      exit 2
      ;;
  esac
fi
