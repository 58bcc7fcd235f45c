#!/usr/bin/env bash
# The main job on the example data shipped in the repo: installs dependencies if needed, builds,
# estimates the relative pose of the real example pairs with the hybrid estimator and the point-only
# baseline, and prints the results (pose errors against the ground truth, focal errors, time).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$ROOT/build}"
bash "$ROOT/scripts/build.sh" >&2
MADSFM="$BUILD_DIR/madsfm"
PAIRS="$ROOT/tests/data/example_pairs"

echo "== madsfm pair: 1_eth3d, calibrated (real LightGlue matches, Depth-Anything metric depth)"
"$MADSFM" pair --pair_path "$PAIRS/1_eth3d" --camera_mode calibrated --reproj_threshold 8 --epipolar_threshold 2
echo
echo "== madsfm bench: 1_eth3d, calibrated and shared focal; 20 seeds per method (tau_r 8 px, tau_s 2 px)"
for mode in calibrated shared_focal; do
  "$MADSFM" bench --pairs_path "$PAIRS/1_eth3d" --camera_mode "$mode" --method hybrid,points \
    --num_seeds 20 --num_threads 1 --reproj_threshold 8 --epipolar_threshold 2 2>/dev/null
  echo
done
echo "== madsfm bench: 2_2d3ds, two focal and calibrated; 20 seeds per method (tau_r 16 px, tau_s 1 px)"
for mode in two_focal calibrated; do
  "$MADSFM" bench --pairs_path "$PAIRS/2_2d3ds" --camera_mode "$mode" --method hybrid,points \
    --num_seeds 20 --num_threads 1 --reproj_threshold 16 --epipolar_threshold 1 2>/dev/null
  echo
done
