#!/usr/bin/env bash
# The sweep every estimator change is measured on (docs/benchmarks.md section 11): `madsfm bench` on the 20 synthetic
# hard_* sets (development: --seed 1, 30 pairs per preset; held-out: --seed 7, 40 pairs) plus any extra pair lists
# (rendered pairs of scripts/bench/rendered_pair_set.sh, real RGB-D pairs), NUM_SEEDS seeds each, two sets at a time.
# Two-focal sets use 16 / 1 px (reprojection / Sampson) as madpose's examples, the others 8 / 2 px.
#   bash scripts/bench/estimator_sweep.sh MADSFM OUT [NUM_SEEDS]
# Env: METHOD (default hybrid; any `bench --method` list), SETS_DIR (where the synthetic sets are written / reused,
#      default OUT/sets), EXTRA="LIST:MODE ..." (e.g. "r/calib.txt:calibrated r/shared.txt:shared_focal"),
#      BENCH_ARGS (more `bench` options, e.g. "--max_shift_ratio 0").
# Compare two sweeps with scripts/bench/sweep_table.py OUT_BEFORE OUT_AFTER.
set -euo pipefail
M="$1"; OUT="$2"; SEEDS="${3:-3}"
METHOD="${METHOD:-hybrid}"; SETS="${SETS_DIR:-$OUT/sets}"
mkdir -p "$OUT" "$SETS"
PRESETS=$("$M" synth --help 2>&1 | grep -o 'hard_[a-z_]*' | sort -u)
jobs=()
for preset in $PRESETS; do
  for split in dev:1:30 held:7:40; do
    IFS=: read -r tag seed n <<<"$split"
    dir="$SETS/$tag/$preset"
    [ -f "$dir/pairs.txt" ] || "$M" synth --preset "$preset" --num_pairs "$n" --seed "$seed" --output_path "$dir" >/dev/null
    case $preset in *two_focal) mode=two_focal ;; *shared_focal) mode=shared_focal ;; *) mode=calibrated ;; esac
    jobs+=("$dir/pairs.txt $mode $tag-${preset#hard_}")
  done
done
for extra in ${EXTRA:-}; do
  list="${extra%:*}"; mode="${extra##*:}"
  jobs+=("$list $mode $(basename "$(dirname "$list")")-$(basename "$list" .txt)-$mode")
done
run_one() {
  local list=$1 mode=$2 tag=$3 th=()
  [ "$mode" = two_focal ] && th=(--reproj_threshold 16 --epipolar_threshold 1)
  # shellcheck disable=SC2086
  "$M" bench --pairs_path "$list" --camera_mode "$mode" --method "$METHOD" --num_seeds "$SEEDS" --num_threads 1 \
    "${th[@]}" ${BENCH_ARGS:-} --output_path "$OUT/$tag" >"$OUT/$tag.log" 2>&1 || echo "bench failed for $tag (see $OUT/$tag.log)" >&2
}
export -f run_one; export M METHOD SEEDS OUT BENCH_ARGS
printf '%s\n' "${jobs[@]}" | xargs -P 2 -L 1 bash -c 'run_one "$@"' _
echo "sweep written to $OUT (${#jobs[@]} sets)"
