#!/usr/bin/env bash
# scripts/slurm on a real (private, single-node) Slurm cluster, with a stand-in for madsfm that records its
# calls: submit.sh's array job runs one task per shard and the merge job starts only after all of them
# succeeded, with every shard file; a failing shard cancels the merge; rerunning just that shard with
# MADSFM_ARRAY_INDICES completes the merge. Needs no madsfm build. Exits 77 ("SKIPPED: <reason>") when the
# daemons cannot start here (not root, Slurm or munge missing, ...). Usage: slurm_cluster_test.sh
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
# shellcheck source=tests/slurm/local_cluster.sh
source "$HERE/local_cluster.sh"
TIMEOUT="${MADSFM_SLURM_TIMEOUT:-90}"

WORK="$(mktemp -d "${TMPDIR:-/tmp}/madsfm_slurm_cluster.XXXXXX")"
cleanup() {
  cluster_stop "$WORK/cluster"
  rm -rf "$WORK"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

if ! cluster_start "$WORK/cluster"; then
  echo "SKIPPED: cannot start a local Slurm cluster: $CLUSTER_ERROR"
  exit 77
fi
echo "local Slurm cluster up ($SLURM_CONF)"

# The stand-in: one line per call with its arguments and start/end times; a shard takes a second, writes its
# shard file, and fails instead when it is STUB_FAIL_SHARD.
cat >"$WORK/madsfm" <<'EOF'
#!/usr/bin/env bash
set -euo pipefail
if [[ "${2:-}" == --help ]]; then printf '  --num_shards INT\n  --seed INT\n'; exit 0; fi
start="$(date +%s.%N)"
args=("$@")
for ((i = 0; i + 1 < $#; i++)); do
  case "${args[i]}" in
    --shard_index) index="${args[i + 1]}" ;;
    --shard_path) shard_path="${args[i + 1]}" ;;
  esac
done
status=0
if [[ "$1" == two_view_estimator ]]; then
  sleep 1
  if [[ "$index" == "${STUB_FAIL_SHARD:-}" ]]; then status=3; else touch "$shard_path"; fi
fi
echo "$* start=$start end=$(date +%s.%N)" >>"$STUB_LOG"
exit "$status"
EOF
chmod +x "$WORK/madsfm"
mkdir -p "$WORK/project/depths"
printf 'SQLite format 3\0' >"$WORK/project/database.db"

failures=0
check() {
  local what="$1"
  shift
  if "$@"; then echo "ok:   $what"; else
    echo "FAIL: $what"
    failures=$((failures + 1))
  fi
}

# submit RUN [VAR=value ...]: submit.sh with shards in $WORK/shards_RUN... (RUN names the stub log too); sets
# ARRAY_JOB and MERGE_JOB; waits for the merge job.
submit() {
  local run="$1" out t0="$SECONDS"
  shift
  out="$(env MADSFM_BIN="$WORK/madsfm" MADSFM_DATABASE="$WORK/project/database.db" \
    MADSFM_DEPTH_PATH="$WORK/project/depths" MADSFM_NUM_SHARDS=4 MADSFM_SHARD_DIR="$WORK/shards" \
    MADSFM_EXTRA_ARGS="--seed 7" STUB_LOG="$WORK/$run.log" "$@" bash "$ROOT/scripts/slurm/submit.sh")" || {
    echo "FAIL: $run: submit.sh failed"
    exit 1
  }
  ARRAY_JOB="$(sed -n 's/^MADSFM_ARRAY_JOB_ID=//p' <<<"$out")"
  MERGE_JOB="$(sed -n 's/^MADSFM_MERGE_JOB_ID=//p' <<<"$out")"
  echo "$run: array job $ARRAY_JOB, merge job $MERGE_JOB"
  if ! cluster_wait_job "$MERGE_JOB" "$TIMEOUT"; then
    echo "FAIL: $run: merge job $MERGE_JOB still not done after $TIMEOUT s"
    scontrol show job "$ARRAY_JOB" "$MERGE_JOB" || true
    failures=$((failures + 1))
  fi
  echo "$run: done after $((SECONDS - t0)) s"
  touch "$WORK/$run.log"
}

states() { cluster_job_states "$1" | sort | tr '\n' ' '; }
# The shard indices run, sorted, from a stub log.
shard_indices() { grep -o -- '--shard_index [0-9]*' "$1" | cut -d' ' -f2 | sort -n | tr '\n' ' '; }
# Latest end of the shards and start of the merge, from a stub log.
last_shard_end() { grep '^two_view_estimator' "$1" | sed 's/.* end=//' | sort -g | tail -n 1; }
merge_start() { grep '^merge_shards' "$1" | sed 's/.* start=\([0-9.]*\) .*/\1/'; }
after() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a != "" && b != "" && a + 0 >= b + 0) }'; }
s="$WORK/shards/shard"
merge_call="merge_shards --database_path $WORK/project/database.db --uncovered_path"
merge_call+=" $WORK/shards/uncovered_pairs_of_4.txt --progress 0"
merge_call+=" ${s}_0_of_4.sqlite ${s}_1_of_4.sqlite ${s}_2_of_4.sqlite ${s}_3_of_4.sqlite"

echo "== 4 shards, then the merge"
submit run1
check "all 4 array tasks completed" test "$(states "$ARRAY_JOB")" = "COMPLETED COMPLETED COMPLETED COMPLETED "
check "the merge job completed" test "$(states "$MERGE_JOB")" = "COMPLETED "
check "each shard ran once: 0 1 2 3" test "$(shard_indices "$WORK/run1.log")" = "0 1 2 3 "
check "shards got --num_shards 4, one thread, the extra options" \
  test "$(grep -c -- '--num_threads 1 --num_shards 4 .* --progress 0 --seed 7 start=' "$WORK/run1.log")" = 4
check "the merge got all 4 shard files" grep -qF -- "$merge_call" "$WORK/run1.log"
check "the merge started after the last shard ended" \
  after "$(merge_start "$WORK/run1.log")" "$(last_shard_end "$WORK/run1.log")"
check "a log per task and one for the merge" test -s "$WORK/shards/logs/two_view_${ARRAY_JOB}_3.log" -a \
  -s "$WORK/shards/logs/merge_${MERGE_JOB}.log"

echo "== shard 2 fails: no merge"
rm -f "$WORK"/shards/shard_*
submit run2 STUB_FAIL_SHARD=2
check "task 2 failed, the others completed" \
  test "$(states "$ARRAY_JOB")" = "COMPLETED COMPLETED COMPLETED FAILED "
check "the merge job was cancelled" test "$(states "$MERGE_JOB")" = "CANCELLED "
check "the merge never ran" test "$(grep -c '^merge_shards' "$WORK/run2.log")" = 0

echo "== rerun of shard 2 alone, then the merge"
submit run3 MADSFM_ARRAY_INDICES=2
check "only shard 2 ran" test "$(shard_indices "$WORK/run3.log")" = "2 "
check "the merge job completed" test "$(states "$MERGE_JOB")" = "COMPLETED "
check "the merge got all 4 shard files" grep -qF -- "$merge_call" "$WORK/run3.log"

if ((failures > 0)); then
  echo "---- job logs"
  for f in "$WORK"/shards/logs/*; do
    echo "-- $f"
    cat "$f"
  done
  cluster_print_logs "$WORK/cluster"
  echo "slurm_cluster_test: $failures check(s) failed"
  exit 1
fi
echo "slurm_cluster_test: all checks passed"
