#!/usr/bin/env bash
# Submits sharded two-view estimation to Slurm: an array job with one task per shard (two_view_shards.sbatch,
# each task writes MADSFM_SHARD_DIR/shard_K_of_N.sqlite and only reads the database) and a merge job
# (merge_shards.sbatch) that waits for all of them with --dependency=afterok. Parameters are environment
# variables, checked here before anything is queued; `submit.sh --help` lists them, docs/cluster.md explains.
# Assumes a filesystem shared by the submit host and the compute nodes for the binary, the database, the
# depth maps and MADSFM_SHARD_DIR.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

usage() {
  cat <<'EOF'
Usage: MADSFM_BIN=... MADSFM_DATABASE=... MADSFM_DEPTH_PATH=... MADSFM_NUM_SHARDS=N MADSFM_SHARD_DIR=... \
         scripts/slurm/submit.sh

Required:
  MADSFM_BIN             the madsfm executable (a path, or a name on PATH)
  MADSFM_DATABASE        the COLMAP database; the shards only read it, the merge job writes it
  MADSFM_DEPTH_PATH      folder of depth sidecars (docs/formats.md)
  MADSFM_NUM_SHARDS      number of shards = array tasks (the split is deterministic, balanced by match count)
  MADSFM_SHARD_DIR       folder for shard_K_of_N.sqlite (created if missing); one folder per database and options
Optional:
  MADSFM_EXTRA_ARGS      further two_view_estimator options, identical for every shard, e.g. "--seed 7"
  MADSFM_CPUS_PER_TASK   cores per shard, passed on as --num_threads (default 1)
  MADSFM_PARTITION       Slurm partition (both jobs)
  MADSFM_ACCOUNT         Slurm account (both jobs)
  MADSFM_TIME            time limit of each shard task (sbatch --time format, e.g. 2:00:00)
  MADSFM_MERGE_TIME      time limit of the merge job
  MADSFM_MEM             memory per shard task (sbatch --mem format, e.g. 4G)
  MADSFM_ARRAY_THROTTLE  at most this many shards running at once
  MADSFM_ARRAY_INDICES   only these shards, e.g. "3,7" to rerun failed ones (default 0-(N-1)); the merge
                         job still merges all N shard files
  MADSFM_LOG_DIR         job logs (default MADSFM_SHARD_DIR/logs)
  MADSFM_SBATCH_ARGS     further sbatch options for both jobs, e.g. "--qos=long"
Prints the two job ids, then MADSFM_ARRAY_JOB_ID=... and MADSFM_MERGE_JOB_ID=... lines for scripts.
EOF
}

fail() {
  echo "submit.sh: error: $*" >&2
  exit 1
}

require() {
  [[ -n "${!1:-}" ]] || fail "$1 is not set ($2); see scripts/slurm/submit.sh --help"
}

is_positive_int() { [[ "$1" =~ ^[1-9][0-9]*$ ]]; }

# Options the scripts set themselves; a second value in MADSFM_EXTRA_ARGS would contradict the split.
RESERVED_OPTIONS=(database_path depth_path num_threads num_shards shard_index shard_path)

check_extra_args() {
  local arg name
  for arg in "$@"; do
    for name in "${RESERVED_OPTIONS[@]}"; do
      if [[ "$arg" == "--$name" || "$arg" == "--$name="* ]]; then
        fail "MADSFM_EXTRA_ARGS must not contain --$name (submit.sh sets it; see --help)"
      fi
    done
  done
}

# Array indices like "0-3" or "2,5,8-9", each below num_shards.
check_array_indices() {
  local indices="$1" num_shards="$2" n
  [[ "$indices" =~ ^[0-9]+(-[0-9]+)?(,[0-9]+(-[0-9]+)?)*$ ]] ||
    fail "MADSFM_ARRAY_INDICES='$indices' is not a list of shard indices like 3,7 or 0-9"
  for n in $(tr ',-' '  ' <<<"$indices"); do
    ((10#$n < num_shards)) || fail "MADSFM_ARRAY_INDICES='$indices': shard $n does not exist (0 to $((num_shards - 1)))"
  done
}

# The job id of `sbatch --parsable` output ("12345" or "12345;cluster").
job_id_of() {
  local id="${1%%;*}"
  [[ "$id" =~ ^[0-9]+$ ]] || return 1
  echo "$id"
}

if (($# > 0)); then
  if [[ "$1" == "-h" || "$1" == "--help" ]]; then
    usage
    exit 0
  fi
  fail "unexpected argument '$1': the parameters are environment variables (see --help)"
fi

require MADSFM_BIN "the madsfm executable"
require MADSFM_DATABASE "the COLMAP database"
require MADSFM_DEPTH_PATH "the folder of depth sidecars"
require MADSFM_NUM_SHARDS "the number of shards"
require MADSFM_SHARD_DIR "the folder for the shard files"

command -v sbatch >/dev/null 2>&1 || fail "sbatch not found: run this on a Slurm submit host (Debian: slurm-client)"

# Absolute paths throughout: the jobs run in MADSFM_SHARD_DIR, on other nodes.
bin="$MADSFM_BIN"
if [[ "$bin" != */* ]]; then
  bin="$(command -v "$bin" 2>/dev/null)" || fail "MADSFM_BIN='$MADSFM_BIN' is not on PATH"
fi
[[ -f "$bin" && -x "$bin" ]] || fail "MADSFM_BIN='$MADSFM_BIN' is not an executable file"
bin="$(realpath -- "$bin")"

[[ -f "$MADSFM_DATABASE" && -r "$MADSFM_DATABASE" ]] ||
  fail "MADSFM_DATABASE='$MADSFM_DATABASE' is not a readable file"
[[ "$(head -c 15 -- "$MADSFM_DATABASE")" == "SQLite format 3" ]] ||
  fail "MADSFM_DATABASE='$MADSFM_DATABASE' is not an SQLite database"
database="$(realpath -- "$MADSFM_DATABASE")"

[[ -d "$MADSFM_DEPTH_PATH" ]] || fail "MADSFM_DEPTH_PATH='$MADSFM_DEPTH_PATH' is not a folder"
depth_path="$(realpath -- "$MADSFM_DEPTH_PATH")"

is_positive_int "$MADSFM_NUM_SHARDS" || fail "MADSFM_NUM_SHARDS='$MADSFM_NUM_SHARDS' is not a positive integer"
num_shards="$MADSFM_NUM_SHARDS"
cpus="${MADSFM_CPUS_PER_TASK:-1}"
is_positive_int "$cpus" || fail "MADSFM_CPUS_PER_TASK='$cpus' is not a positive integer"
throttle="${MADSFM_ARRAY_THROTTLE:-}"
[[ -z "$throttle" ]] || is_positive_int "$throttle" ||
  fail "MADSFM_ARRAY_THROTTLE='$throttle' is not a positive integer"
indices="${MADSFM_ARRAY_INDICES:-0-$((num_shards - 1))}"
check_array_indices "$indices" "$num_shards"

# Array task ids must stay below the cluster's MaxArraySize; asking first beats a cryptic sbatch refusal.
max_array_size="$(scontrol show config 2>/dev/null | awk '$1 == "MaxArraySize" { print $3 }')" || true
if [[ "$max_array_size" =~ ^[0-9]+$ ]] && ((num_shards > max_array_size)); then
  fail "MADSFM_NUM_SHARDS=$num_shards exceeds this cluster's MaxArraySize=$max_array_size"
fi

read -r -a extra_args <<<"${MADSFM_EXTRA_ARGS:-}"
check_extra_args "${extra_args[@]}"
read -r -a sbatch_extra <<<"${MADSFM_SBATCH_ARGS:-}"

mkdir -p -- "$MADSFM_SHARD_DIR" || fail "MADSFM_SHARD_DIR='$MADSFM_SHARD_DIR' cannot be created"
[[ -w "$MADSFM_SHARD_DIR" ]] || fail "MADSFM_SHARD_DIR='$MADSFM_SHARD_DIR' is not writable"
shard_dir="$(realpath -- "$MADSFM_SHARD_DIR")"
log_dir="${MADSFM_LOG_DIR:-$shard_dir/logs}"
mkdir -p -- "$log_dir" || fail "MADSFM_LOG_DIR='$log_dir' cannot be created"
log_dir="$(realpath -- "$log_dir")"

# A binary without the shard options would fail in every task; catch it before queueing anything. A binary
# that cannot run here at all (another architecture than the compute nodes) is left to the jobs.
if help_text="$("$bin" two_view_estimator --help 2>&1)"; then
  [[ "$help_text" == *--num_shards* ]] ||
    fail "MADSFM_BIN='$bin' has no two_view_estimator --num_shards (a madsfm without sharding?)"
  if [[ -n "${extra_args[*]}" ]]; then
    for arg in "${extra_args[@]}"; do
      name="${arg%%=*}"
      [[ "$name" != --* || "$help_text" =~ (^|[[:space:]])"$name"([[:space:]]|$) ]] ||
        fail "MADSFM_EXTRA_ARGS: two_view_estimator has no option $name (see $bin two_view_estimator --help)"
    done
  fi
else
  echo "submit.sh: warning: '$bin two_view_estimator --help' does not run on this host; the jobs will tell" >&2
fi

export MADSFM_BIN="$bin" MADSFM_DATABASE="$database" MADSFM_DEPTH_PATH="$depth_path" \
  MADSFM_NUM_SHARDS="$num_shards" MADSFM_SHARD_DIR="$shard_dir" MADSFM_EXTRA_ARGS="${extra_args[*]}"

common=(--parsable --export=ALL --chdir="$shard_dir" "${sbatch_extra[@]}")
[[ -z "${MADSFM_PARTITION:-}" ]] || common+=(--partition="$MADSFM_PARTITION")
[[ -z "${MADSFM_ACCOUNT:-}" ]] || common+=(--account="$MADSFM_ACCOUNT")

array_opts=(--array="$indices${throttle:+%$throttle}" --cpus-per-task="$cpus" --output="$log_dir/two_view_%A_%a.log")
[[ -z "${MADSFM_TIME:-}" ]] || array_opts+=(--time="$MADSFM_TIME")
[[ -z "${MADSFM_MEM:-}" ]] || array_opts+=(--mem="$MADSFM_MEM")
out="$(sbatch "${common[@]}" "${array_opts[@]}" "$HERE/two_view_shards.sbatch")" ||
  fail "sbatch refused the shard array job (its message is above)"
array_job="$(job_id_of "$out")" || fail "unexpected answer from sbatch --parsable: '$out'"

# --kill-on-invalid-dep: when a shard fails the merge job is cancelled instead of pending forever.
merge_opts=(--dependency="afterok:$array_job" --kill-on-invalid-dep=yes --cpus-per-task=1
  --output="$log_dir/merge_%j.log")
[[ -z "${MADSFM_MERGE_TIME:-}" ]] || merge_opts+=(--time="$MADSFM_MERGE_TIME")
if ! out="$(sbatch "${common[@]}" "${merge_opts[@]}" "$HERE/merge_shards.sbatch")" ||
  ! merge_job="$(job_id_of "$out")"; then
  fail "shard array job $array_job is queued, but sbatch refused the merge job; submit it yourself:" \
    "sbatch --dependency=afterok:$array_job --export=ALL $HERE/merge_shards.sbatch (same MADSFM_* variables)"
fi

cat <<EOF
madsfm: $num_shards shards of $database (tasks $indices, $cpus CPU(s) each): array job $array_job;
        merge into the database: job $merge_job, starts when every task succeeded (cancelled if one fails)
  watch:       squeue -j $array_job,$merge_job      (or: scontrol show job $merge_job)
  shard logs:  $log_dir/two_view_${array_job}_<K>.log
  merge log:   $log_dir/merge_${merge_job}.log
  a shard failed? fix the cause, then rerun it (it resumes from its file) and the merge, e.g.
               MADSFM_ARRAY_INDICES=<K,...> $HERE/submit.sh   (same variables otherwise)
MADSFM_ARRAY_JOB_ID=$array_job
MADSFM_MERGE_JOB_ID=$merge_job
EOF
