#!/usr/bin/env bash
# End to end on a private single-node Slurm cluster (tests/slurm/local_cluster.sh): a generated scene
# (madsfm synth_project) is estimated twice from the same database, once by a single two_view_estimator process
# and once by scripts/slurm/submit.sh as a 4-task array job plus the dependent merge job. The merged database
# must hold exactly the rows of the single-process run, in every table; merging the shards again must change
# nothing. Exits 77 ("SKIPPED: <reason>") when the daemons cannot start here (not root, Slurm or munge
# missing, ...).
# Usage: slurm_e2e.sh MADSFM_BINARY
# Environment: MADSFM_SLURM_E2E_PAIRS (200), MADSFM_SLURM_E2E_SEED (7), MADSFM_SLURM_TIMEOUT (s, 300),
#              MADSFM_SLURM_E2E_KEEP=1 keeps the work folder.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
# shellcheck source=tests/slurm/local_cluster.sh
source "$HERE/local_cluster.sh"

NUM_SHARDS=4
NUM_PAIRS="${MADSFM_SLURM_E2E_PAIRS:-200}"
SEED="${MADSFM_SLURM_E2E_SEED:-7}"
TIMEOUT="${MADSFM_SLURM_TIMEOUT:-300}"
# Tables the estimation writes (or must leave as they were); they must exist. Every other table of the two
# databases is compared as well.
REQUIRED_TABLES=(two_view_geometries madsfm_two_view_geometries madsfm_backup_two_view_geometries matches cameras)

fail() {
  echo "slurm_e2e: error: $*" >&2
  exit 1
}

(($# == 1)) || fail "usage: slurm_e2e.sh MADSFM_BINARY"
[[ -f "$1" && -x "$1" ]] || fail "madsfm binary '$1' is not an executable file"
MADSFM="$(realpath -- "$1")"
if ! command -v sqlite3 >/dev/null 2>&1; then
  echo "SKIPPED: sqlite3 not found (Debian package sqlite3), needed to compare the databases"
  exit 77
fi

WORK="$(mktemp -d "${TMPDIR:-/tmp}/madsfm_slurm_e2e.XXXXXX")"
cleanup() {
  cluster_stop "$WORK/cluster"
  if [[ "${MADSFM_SLURM_E2E_KEEP:-0}" == 1 ]]; then echo "work folder kept: $WORK"; else rm -rf "$WORK"; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

if ! cluster_start "$WORK/cluster"; then
  echo "SKIPPED: cannot start a local Slurm cluster: $CLUSTER_ERROR"
  exit 77
fi
echo "local Slurm cluster up ($SLURM_CONF, $(nproc) CPUs)"

failures=0
check() {
  local what="$1"
  shift
  if "$@"; then echo "ok:   $what"; else
    echo "FAIL: $what"
    failures=$((failures + 1))
  fi
}

print_logs_and_exit() {
  echo "---- job logs"
  for f in "$WORK"/shards/logs/*; do
    [[ -f "$f" ]] || continue
    echo "-- $f"
    cat "$f"
  done
  echo "-- single-process run"
  cat "$WORK/single.log" 2>/dev/null || true
  scontrol show job "${ARRAY_JOB:-0}" "${MERGE_JOB:-0}" 2>/dev/null || true
  cluster_print_logs "$WORK/cluster"
  echo "slurm_e2e: ${1:-$failures check(s) failed}"
  exit 1
}

# One line per row, every column through quote() (exact: blobs as X'..', reals with as many digits as it takes
# to round-trip), ordered by all columns so that insertion order and rowids do not matter.
dump_table() {
  local db="$1" table="$2" columns values
  columns="$(sqlite3 "$db" "SELECT group_concat('\"' || name || '\"', ',') FROM pragma_table_info('$table')")"
  [[ -n "$columns" ]] || return 1
  values="$(sqlite3 "$db" \
    "SELECT group_concat('quote(\"' || name || '\")', ' || '','' || ') FROM pragma_table_info('$table')")"
  sqlite3 "$db" "SELECT $values FROM \"$table\" ORDER BY $columns"
}

schema_of() { sqlite3 "$1" "SELECT name || ' ' || type FROM pragma_table_info('$2')"; }
count_rows() { sqlite3 "$1" "SELECT count(*) FROM \"$2\""; }

# The merged table equals the single-process one: same columns, same rows. Prints the first differences.
tables_equal() {
  local table="$1" single="$WORK/dump_single_$1.txt" sharded="$WORK/dump_sharded_$1.txt"
  if ! dump_table "$WORK/single.db" "$table" >"$single"; then
    echo "      no table $table in the single-process database"
    return 1
  fi
  if ! dump_table "$WORK/sharded.db" "$table" >"$sharded"; then
    echo "      no table $table in the merged database"
    return 1
  fi
  if [[ "$(schema_of "$WORK/single.db" "$table")" != "$(schema_of "$WORK/sharded.db" "$table")" ]]; then
    echo "      columns differ: single-process ($(schema_of "$WORK/single.db" "$table" | tr '\n' ,))" \
      "merged ($(schema_of "$WORK/sharded.db" "$table" | tr '\n' ,))"
    return 1
  fi
  if ! cmp -s "$single" "$sharded"; then
    echo "      rows differ (< single-process, > merged; first lines of the diff):"
    diff "$single" "$sharded" | head -n 10 | cut -c 1-200 | sed 's/^/      /'
    return 1
  fi
}

echo "== scene: $NUM_PAIRS pairs (seed $SEED)"
"$MADSFM" synth_project --output_path "$WORK/scene" --num_pairs "$NUM_PAIRS" --seed "$SEED" >"$WORK/synth.log" 2>&1 ||
  {
    cat "$WORK/synth.log"
    fail "madsfm synth_project failed"
  }
# Like a real COLMAP project, half the pairs already have COLMAP's verified geometry (which madsfm backs up),
# and two images have no depth map (their pairs take the point-only fallback).
sqlite3 "$WORK/scene/database.db" "INSERT INTO two_view_geometries (pair_id, rows, cols, data, config, F)
  SELECT pair_id, rows, cols, data, 3, zeroblob(72) FROM matches WHERE (pair_id >> 31) % 4 < 2"
rm -f "$WORK/scene/depths/pair1_a.png.npy" "$WORK/scene/depths/pair2_b.png.npy"
cp "$WORK/scene/database.db" "$WORK/single.db"
cp "$WORK/scene/database.db" "$WORK/sharded.db"

echo "== single process"
t0="$(date +%s.%N)"
# Two threads against one per shard: the result may depend neither on the split nor on the thread count.
if ! "$MADSFM" two_view_estimator --database_path "$WORK/single.db" --depth_path "$WORK/scene/depths" \
  --num_threads 2 --seed "$SEED" --progress 0 >"$WORK/single.log" 2>&1; then
  print_logs_and_exit "the single-process two_view_estimator failed"
fi
t_single="$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')"

echo "== Slurm: $NUM_SHARDS shards + merge"
t0="$(date +%s.%N)"
if ! out="$(env MADSFM_BIN="$MADSFM" MADSFM_DATABASE="$WORK/sharded.db" MADSFM_DEPTH_PATH="$WORK/scene/depths" \
  MADSFM_NUM_SHARDS="$NUM_SHARDS" MADSFM_SHARD_DIR="$WORK/shards" MADSFM_CPUS_PER_TASK=1 \
  MADSFM_EXTRA_ARGS="--seed $SEED" bash "$ROOT/scripts/slurm/submit.sh" 2>&1)"; then
  echo "$out"
  print_logs_and_exit "scripts/slurm/submit.sh failed"
fi
echo "$out"
ARRAY_JOB="$(sed -n 's/^MADSFM_ARRAY_JOB_ID=//p' <<<"$out")"
MERGE_JOB="$(sed -n 's/^MADSFM_MERGE_JOB_ID=//p' <<<"$out")"
cluster_wait_job "$MERGE_JOB" "$TIMEOUT" || print_logs_and_exit "merge job $MERGE_JOB not done after $TIMEOUT s"
t_slurm="$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')"

array_states="$(cluster_job_states "$ARRAY_JOB" | sort | uniq -c | awk '{ printf "%s %s ", $1, $2 }')"
check "all $NUM_SHARDS array tasks completed ($array_states)" test "$array_states" = "$NUM_SHARDS COMPLETED "
check "the merge job completed" test "$(cluster_job_states "$MERGE_JOB")" = COMPLETED
for ((k = 0; k < NUM_SHARDS; k++)); do
  check "shard file $k of $NUM_SHARDS written" test -s "$WORK/shards/shard_${k}_of_${NUM_SHARDS}.sqlite"
done
((failures == 0)) || print_logs_and_exit

echo "== merged database vs single-process run: every table"
# Equal empty tables would prove nothing: the estimation must have written rows.
for table in two_view_geometries madsfm_two_view_geometries madsfm_backup_two_view_geometries; do
  check "the single-process run wrote $table" \
    test "$(count_rows "$WORK/single.db" "$table" 2>/dev/null || echo 0)" -gt 0
done
list_tables() { sqlite3 "$1" "SELECT name FROM sqlite_master WHERE type = 'table' ORDER BY 1"; }
mapfile -t TABLES < <(sort -u <(list_tables "$WORK/single.db") <(list_tables "$WORK/sharded.db"))
for table in "${REQUIRED_TABLES[@]}"; do
  check "table $table exists" grep -qxF "$table" <(list_tables "$WORK/single.db")
done
for table in "${TABLES[@]}"; do
  check "$table identical" tables_equal "$table"
done

# A second merge of the same shards changes nothing.
if "$MADSFM" merge_shards --database_path "$WORK/sharded.db" "$WORK"/shards/shard_*_of_"$NUM_SHARDS".sqlite \
  >"$WORK/merge_again.log" 2>&1; then
  for table in "${TABLES[@]}"; do
    check "$table still identical after merging the shards again" tables_equal "$table"
  done
else
  check "merging the same shards again succeeds: $(tail -n 3 "$WORK/merge_again.log")" false
fi

echo "== summary"
printf '| table | rows (single process) | rows (merged) |\n|---|---|---|\n'
for table in "${TABLES[@]}"; do
  printf '| %s | %s | %s |\n' "$table" "$(count_rows "$WORK/single.db" "$table" 2>/dev/null || echo -)" \
    "$(count_rows "$WORK/sharded.db" "$table" 2>/dev/null || echo -)"
done
echo "single process (2 threads): $t_single s; Slurm, $NUM_SHARDS shards x 1 CPU + merge, incl. scheduling: $t_slurm s"
((failures == 0)) || print_logs_and_exit
echo "slurm_e2e: merged database identical to the single-process run"
