#!/usr/bin/env bash
# The Slurm scripts without a cluster: scripts/slurm/submit.sh against stand-ins for sbatch, scontrol and
# madsfm (the sbatch options it composes, the job id it chains, every refusal of bad parameters, naming the
# variable), and the two batch scripts run directly with the environment Slurm would give them.
# Runs anywhere (no root, no daemons). Usage: slurm_scripts_test.sh
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
SUBMIT="$ROOT/scripts/slurm/submit.sh"
SHARDS_SBATCH="$ROOT/scripts/slurm/two_view_shards.sbatch"
MERGE_SBATCH="$ROOT/scripts/slurm/merge_shards.sbatch"
WORK="$(mktemp -d "${TMPDIR:-/tmp}/madsfm_slurm_scripts.XXXXXX")"
trap 'rm -rf "$WORK"' EXIT
cd "$WORK"  # whatever a script under test writes by mistake lands here

failures=0
check() {  # check DESCRIPTION COMMAND...: one ok/FAIL line per assertion
  local what="$1"
  shift
  if "$@"; then
    echo "ok:   $what"
  else
    echo "FAIL: $what"
    failures=$((failures + 1))
  fi
}
contains() { [[ "$1" == *"$2"* ]]; }
lacks() { [[ "$1" != *"$2"* ]]; }
refused() { [[ "$1" != 0 && "$2" == *"$3"* ]]; }  # refused STATUS OUTPUT MESSAGE
has_line() { grep -qxF -- "$2" "$1"; }

# --- stand-ins ------------------------------------------------------------------------------------------------
FAKE="$WORK/fakebin"
mkdir -p "$FAKE"
# sbatch: one line per call (its arguments, then the environment the job would get), answers job ids 100, 101,
# ... in the `--parsable` format, the second with a cluster suffix as on federated clusters; FAKE_SBATCH_FAIL=1
# refuses.
cat >"$FAKE/sbatch" <<'EOF'
#!/usr/bin/env bash
set -euo pipefail
if [[ "${FAKE_SBATCH_FAIL:-0}" == 1 ]]; then echo "sbatch: error: Invalid partition name specified" >&2; exit 1; fi
n=$(( $(wc -l <"$FAKE_SBATCH_LOG") ))
echo "$* | db=$MADSFM_DATABASE depth=$MADSFM_DEPTH_PATH shards=$MADSFM_SHARD_DIR bin=$MADSFM_BIN" \
  "extra=$MADSFM_EXTRA_ARGS" >>"$FAKE_SBATCH_LOG"
if ((n == 0)); then echo 100; else echo "$((100 + n));cluster"; fi
EOF
cat >"$FAKE/scontrol" <<'EOF'
#!/usr/bin/env bash
[[ "$*" == "show config" ]] && echo "MaxArraySize            = 6"
EOF
# madsfm: help texts like the real one's, and a record of every real call.
cat >"$WORK/madsfm" <<'EOF'
#!/usr/bin/env bash
set -euo pipefail
if [[ "${2:-}" == --help ]]; then
  printf '  --database_path TEXT  (required)\n  --seed INT  (default: 0)\n'
  [[ "${FAKE_OLD_MADSFM:-0}" == 1 ]] || printf '  --num_shards INT  (default: 1)\n'
  exit 0
fi
echo "$*" >>"$FAKE_MADSFM_LOG"
if [[ "$1" == merge_shards ]]; then
  # Like the real one: the header always, then FAKE_UNCOVERED pairs.
  echo "# pairs no shard covered" >"$5"
  for ((i = 0; i < ${FAKE_UNCOVERED:-0}; i++)); do echo "pair${i}_a.png pair${i}_b.png" >>"$5"; done
fi
exit "${FAKE_MADSFM_STATUS:-0}"
EOF
chmod +x "$FAKE/sbatch" "$FAKE/scontrol" "$WORK/madsfm"
export FAKE_SBATCH_LOG="$WORK/sbatch.log" FAKE_MADSFM_LOG="$WORK/madsfm.log"

mkdir -p "$WORK/project/depths"
printf 'SQLite format 3\0' >"$WORK/project/database.db"
echo "not a database" >"$WORK/project/notes.txt"

# submit.sh from inside $WORK with relative paths (it must make them absolute for the jobs); arguments are
# overriding VAR=value assignments (VAR= unsets); prints the output, returns the status.
run_submit() {
  : >"$FAKE_SBATCH_LOG"
  (cd "$WORK" && env PATH="$FAKE:$PATH" MADSFM_BIN=./madsfm MADSFM_DATABASE=project/database.db \
    MADSFM_DEPTH_PATH=project/depths MADSFM_NUM_SHARDS=4 MADSFM_SHARD_DIR=shards MADSFM_EXTRA_ARGS= \
    MADSFM_CPUS_PER_TASK= MADSFM_PARTITION= MADSFM_ARRAY_INDICES= MADSFM_ARRAY_THROTTLE= MADSFM_TIME= \
    MADSFM_MEM= MADSFM_LOG_DIR= MADSFM_SBATCH_ARGS= "$@" bash "$SUBMIT" 2>&1)
}

# A refusal: status 1, the message names the problem, and nothing was submitted.
expect_refusal() {
  local message="$1" out status=0
  shift
  out="$(run_submit "$@")" || status=$?
  if ((status == 1)) && contains "$out" "$message" && [[ ! -s "$FAKE_SBATCH_LOG" ]]; then
    echo "ok:   refuses $* ($out)"
  else
    echo "FAIL: $* should be refused with '$message', got status $status: $out"
    failures=$((failures + 1))
  fi
}

echo "== submit.sh refuses bad parameters before submitting anything"
expect_refusal "MADSFM_BIN is not set" MADSFM_BIN=
expect_refusal "MADSFM_DATABASE is not set" MADSFM_DATABASE=
expect_refusal "MADSFM_DEPTH_PATH is not set" MADSFM_DEPTH_PATH=
expect_refusal "MADSFM_NUM_SHARDS is not set" MADSFM_NUM_SHARDS=
expect_refusal "MADSFM_SHARD_DIR is not set" MADSFM_SHARD_DIR=
expect_refusal "MADSFM_BIN='./missing' is not an executable file" MADSFM_BIN=./missing
expect_refusal "MADSFM_BIN='no-such-madsfm' is not on PATH" MADSFM_BIN=no-such-madsfm
expect_refusal "MADSFM_DATABASE='project/missing.db' is not a readable file" MADSFM_DATABASE=project/missing.db
expect_refusal "MADSFM_DATABASE='project/notes.txt' is not an SQLite database" MADSFM_DATABASE=project/notes.txt
expect_refusal "MADSFM_DEPTH_PATH='project/nodepths' is not a folder" MADSFM_DEPTH_PATH=project/nodepths
expect_refusal "MADSFM_NUM_SHARDS='0' is not a positive integer" MADSFM_NUM_SHARDS=0
expect_refusal "MADSFM_NUM_SHARDS='four' is not a positive integer" MADSFM_NUM_SHARDS=four
expect_refusal "MADSFM_NUM_SHARDS=7 exceeds this cluster's MaxArraySize=6" MADSFM_NUM_SHARDS=7
expect_refusal "MADSFM_CPUS_PER_TASK='0' is not a positive integer" MADSFM_CPUS_PER_TASK=0
expect_refusal "MADSFM_ARRAY_THROTTLE='-1' is not a positive integer" MADSFM_ARRAY_THROTTLE=-1
expect_refusal "MADSFM_ARRAY_INDICES='1-x' is not a list of shard indices" MADSFM_ARRAY_INDICES=1-x
expect_refusal "MADSFM_ARRAY_INDICES='2,4': shard 4 does not exist" MADSFM_ARRAY_INDICES=2,4
expect_refusal "must not contain --num_threads" "MADSFM_EXTRA_ARGS=--seed 3 --num_threads 8"
expect_refusal "must not contain --shard_index" MADSFM_EXTRA_ARGS=--shard_index=1
expect_refusal "two_view_estimator has no option --sed" "MADSFM_EXTRA_ARGS=--sed 3"
expect_refusal "has no two_view_estimator --num_shards" FAKE_OLD_MADSFM=1
expect_refusal "sbatch refused the shard array job" FAKE_SBATCH_FAIL=1
out="$(cd "$WORK" && env PATH="$FAKE:$PATH" bash "$SUBMIT" extra 2>&1)" && status=0 || status=$?
check "refuses a command-line argument, pointing at the variables" refused "$status" "$out" \
  "unexpected argument 'extra': the parameters are environment variables"

echo "== submit.sh submits the shard array, then the merge after it"
out="$(run_submit MADSFM_CPUS_PER_TASK=2 MADSFM_PARTITION=batch MADSFM_TIME=1:00:00 "MADSFM_EXTRA_ARGS=--seed 7")"
echo "      ${out//$'\n'/$'\n'      }"
mapfile -t calls <"$FAKE_SBATCH_LOG"
check "two sbatch calls" test "${#calls[@]}" = 2
array_call="${calls[0]:-}"
merge_call="${calls[1]:-}"
for opt in --parsable --export=ALL --array=0-3 --cpus-per-task=2 --partition=batch --time=1:00:00 \
  "--chdir=$WORK/shards" "--output=$WORK/shards/logs/two_view_%A_%a.log" \
  "$ROOT/scripts/slurm/two_view_shards.sbatch"; do
  check "array job gets $opt" contains "$array_call" "$opt "
done
check "array job environment: absolute paths, extra options" contains "$array_call" \
  "db=$WORK/project/database.db depth=$WORK/project/depths shards=$WORK/shards bin=$WORK/madsfm extra=--seed 7"
for opt in --dependency=afterok:100 --kill-on-invalid-dep=yes --partition=batch "--chdir=$WORK/shards" \
  "--output=$WORK/shards/logs/merge_%j.log" "$ROOT/scripts/slurm/merge_shards.sbatch"; do
  check "merge job gets $opt" contains "$merge_call" "$opt "
done
check "merge job has no shard time limit" lacks "$merge_call" --time=
check "prints the array job id" contains "$out" "MADSFM_ARRAY_JOB_ID=100"
check "prints the merge job id without the cluster suffix" contains "$out" "MADSFM_MERGE_JOB_ID=101"
check "creates the shard and log folders" test -d "$WORK/shards/logs"

run_submit MADSFM_ARRAY_INDICES=1,3 MADSFM_ARRAY_THROTTLE=2 "MADSFM_SBATCH_ARGS=--qos=long --nice=5" >/dev/null
mapfile -t calls <"$FAKE_SBATCH_LOG"
check "a rerun of shards 1 and 3, at most 2 at once" contains "${calls[0]:-}" "--array=1,3%2 "
check "MADSFM_SBATCH_ARGS reach the array job" contains "${calls[0]:-}" "--qos=long --nice=5 "
check "MADSFM_SBATCH_ARGS reach the merge job" contains "${calls[1]:-}" "--qos=long --nice=5 "

echo "== two_view_shards.sbatch (as Slurm runs it: array task id and cpus in the environment)"
shard_env=(MADSFM_BIN="$WORK/madsfm" MADSFM_DATABASE="$WORK/project/database.db"
  MADSFM_DEPTH_PATH="$WORK/project/depths" MADSFM_NUM_SHARDS=4 MADSFM_SHARD_DIR="$WORK/shards"
  MADSFM_EXTRA_ARGS="--seed 7 --camera_mode two_focal")
: >"$FAKE_MADSFM_LOG"
env "${shard_env[@]}" SLURM_ARRAY_TASK_ID=2 SLURM_CPUS_PER_TASK=3 bash "$SHARDS_SBATCH" >/dev/null
inputs="--database_path $WORK/project/database.db --depth_path $WORK/project/depths"
check "task 2 estimates shard 2 of 4 into its own file with 3 threads" has_line "$FAKE_MADSFM_LOG" \
  "two_view_estimator $inputs --num_threads 3 --num_shards 4 --shard_index 2 \
--shard_path $WORK/shards/shard_2_of_4.sqlite --progress 0 --seed 7 --camera_mode two_focal"
: >"$FAKE_MADSFM_LOG"
env "${shard_env[@]}" MADSFM_EXTRA_ARGS= SLURM_ARRAY_TASK_ID=0 bash "$SHARDS_SBATCH" >/dev/null
check "one thread without --cpus-per-task, no extra options" has_line "$FAKE_MADSFM_LOG" \
  "two_view_estimator $inputs --num_threads 1 --num_shards 4 --shard_index 0 \
--shard_path $WORK/shards/shard_0_of_4.sqlite --progress 0"
status=0
env "${shard_env[@]}" SLURM_ARRAY_TASK_ID=1 FAKE_MADSFM_STATUS=3 bash "$SHARDS_SBATCH" >/dev/null || status=$?
check "the task fails with madsfm's exit status (so afterok holds the merge back)" test "$status" = 3
out="$(env "${shard_env[@]}" SLURM_ARRAY_TASK_ID=4 bash "$SHARDS_SBATCH" 2>&1)" && status=0 || status=$?
check "task 4 of 4 shards is refused ($out)" refused "$status" "$out" "array task 4 is not a shard"
out="$(env "${shard_env[@]}" bash "$SHARDS_SBATCH" 2>&1)" && status=0 || status=$?
check "outside an array job: refused ($out)" refused "$status" "$out" "not an array task"
out="$(env "${shard_env[@]}" MADSFM_DEPTH_PATH= SLURM_ARRAY_TASK_ID=0 bash "$SHARDS_SBATCH" 2>&1)" && status=0 ||
  status=$?
check "a missing variable is named ($out)" refused "$status" "$out" "MADSFM_DEPTH_PATH is not set"

echo "== merge_shards.sbatch"
merge_env=(MADSFM_BIN="$WORK/madsfm" MADSFM_DATABASE="$WORK/project/database.db" MADSFM_NUM_SHARDS=4
  MADSFM_SHARD_DIR="$WORK/shards")
: >"$FAKE_MADSFM_LOG"
touch "$WORK/shards/shard_0_of_4.sqlite" "$WORK/shards/shard_2_of_4.sqlite" "$WORK/shards/shard_0_of_3.sqlite"
out="$(env "${merge_env[@]}" bash "$MERGE_SBATCH" 2>&1)" && status=0 || status=$?
check "missing shard files are named ($out)" refused "$status" "$out" "shard(s) 1,3 of 4"
check "nothing is merged then" test ! -s "$FAKE_MADSFM_LOG"
touch "$WORK/shards/shard_1_of_4.sqlite" "$WORK/shards/shard_3_of_4.sqlite"
env "${merge_env[@]}" bash "$MERGE_SBATCH" >/dev/null
s="$WORK/shards/shard"
check "merges exactly the 4 files of this split, in shard order" has_line "$FAKE_MADSFM_LOG" \
  "merge_shards --database_path $WORK/project/database.db --uncovered_path $WORK/shards/uncovered_pairs_of_4.txt \
--progress 0 ${s}_0_of_4.sqlite ${s}_1_of_4.sqlite ${s}_2_of_4.sqlite ${s}_3_of_4.sqlite"
status=0
env "${merge_env[@]}" FAKE_MADSFM_STATUS=1 bash "$MERGE_SBATCH" >/dev/null 2>&1 || status=$?
check "a refused merge fails the job" test "$status" = 1
out="$(env "${merge_env[@]}" FAKE_UNCOVERED=2 bash "$MERGE_SBATCH" 2>&1)" && status=0 || status=$?
check "uncovered pairs fail the job, naming the list ($out)" refused "$status" "$out" \
  "2 pairs not covered by any shard (listed in $WORK/shards/uncovered_pairs_of_4.txt)"

if ((failures > 0)); then
  echo "slurm_scripts_test: $failures check(s) failed"
  exit 1
fi
echo "slurm_scripts_test: all checks passed"
