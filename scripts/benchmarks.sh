#!/usr/bin/env bash
# Reproduces the tables of docs/benchmarks.md: solver benchmark, example pairs, synthetic sets, iteration
# trade-off. Single-threaded estimator timings (--num_threads 1). Writes raw outputs to ${OUT:-/tmp/madsfm_bench}.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$ROOT/build}"
OUT="${OUT:-/tmp/madsfm_bench}"
mkdir -p "$OUT"
bash "$ROOT/scripts/build.sh" >&2
M="$BUILD_DIR/madsfm"
P="$ROOT/tests/data/example_pairs"
echo "# machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(date -u +%Y-%m-%d)"

echo "## solver benchmark"
"$BUILD_DIR/tests/bench/madsfm_solver_bench" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_min_time=0.2 2>/dev/null | grep -E "median|Benchmark|---"

echo "## example pairs (20 seeds each)"
run() { "$M" bench --num_threads 1 "$@" 2>/dev/null | tail -n +3; echo; }
run --pairs_path "$P/1_eth3d" --camera_mode calibrated --method hybrid,points,depth_only,no_shift --num_seeds 20 --reproj_threshold 8 --epipolar_threshold 2
run --pairs_path "$P/1_eth3d" --camera_mode shared_focal --method hybrid,points,depth_only,no_shift --num_seeds 20 --reproj_threshold 8 --epipolar_threshold 2
run --pairs_path "$P/2_2d3ds" --camera_mode calibrated --method hybrid,points --num_seeds 20 --reproj_threshold 16 --epipolar_threshold 1
run --pairs_path "$P/2_2d3ds" --camera_mode shared_focal --method hybrid,points --num_seeds 20 --reproj_threshold 16 --epipolar_threshold 1
run --pairs_path "$P/2_2d3ds" --camera_mode two_focal --method hybrid,points,depth_only,no_shift --num_seeds 20 --reproj_threshold 16 --epipolar_threshold 1

echo "## synthetic sets (100 pairs each, madsfm synth --seed 0)"
for spec in indoor_calibrated:calibrated:8:2 outdoor_calibrated:calibrated:16:1 indoor_shared_focal:shared_focal:8:2 \
            indoor_two_focal:two_focal:8:2 outdoor_two_focal:two_focal:16:1 indoor_bad_prior:calibrated:8:2; do
  IFS=: read -r preset mode tr ts <<< "$spec"
  [ -f "$OUT/synth/$preset/pairs.txt" ] || "$M" synth --preset "$preset" --num_pairs 100 --seed 0 --output_path "$OUT/synth/$preset" 2>/dev/null
  echo "### $preset ($mode, tau_r $tr, tau_s $ts)"
  run --pairs_path "$OUT/synth/$preset/pairs.txt" --camera_mode "$mode" --method hybrid,points,depth_only,no_shift --reproj_threshold "$tr" --epipolar_threshold "$ts"
done

echo "## iteration trade-off (hybrid; min_iterations; paper's code uses 1000)"
for it in 20 50 100 200 1000; do
  echo "### min_iterations $it"
  run --pairs_path "$P/1_eth3d" --camera_mode shared_focal --method hybrid --num_seeds 20 --min_iterations "$it"
  run --pairs_path "$P/2_2d3ds" --camera_mode two_focal --method hybrid --num_seeds 20 --min_iterations "$it" --reproj_threshold 16 --epipolar_threshold 1
  run --pairs_path "$OUT/synth/indoor_calibrated/pairs.txt" --camera_mode calibrated --method hybrid --min_iterations "$it"
done

echo "## pipeline throughput (two_view_estimator on 1000 synthetic pairs, 1 and 2 threads)"
"$BUILD_DIR/tests/bench/madsfm_pipeline_bench" 2>/dev/null | grep BM_

echo "## sharding (1, 2, 4 shards as processes; single process; merge of 10,000 pairs)"
"$BUILD_DIR/tests/bench/madsfm_shard_bench" --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
  2>/dev/null | grep -E "median"

echo "## Python thread pool"
if [ -d "$BUILD_DIR/python/madsfm" ]; then
  (cd "$ROOT" && PYTHONPATH="$BUILD_DIR/python" /usr/bin/python3 python/bench/threadpool_bench.py)
else
  echo "(no Python module in $BUILD_DIR/python: skipped)"
fi
