#!/usr/bin/env bash
# madsfm against the paper's code (madpose) and PoseLib on the same pairs, same thresholds, in one run per set:
# generates the hard_* synthetic presets (fixed seed) and runs ../shared/anchors/compare.sh on each and on the
# example pairs. Needs the reference drivers built outside the checkout (../shared/anchors/README.md).
#   ANCHORS_DIR=<folder of bin/> bash scripts/bench/compare_references.sh [NUM_PAIRS] [SEED] [OUT]
# Env: COMPARE=<path of compare.sh> (default ../shared/anchors/compare.sh beside the checkout), SKIP_MADPOSE=1,
#      PRESETS="hard_indoor_calibrated ..." (default: every hard_* preset), THRESHOLDS=paper|fixed (paper: the
#      examples' 8/2 calibrated + shared, 16/1 two focal; fixed: 8/2 everywhere).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
N=${1:-40}; SEED=${2:-7}; OUT=${3:-/tmp/madsfm_compare}
COMPARE=${COMPARE:-$ROOT/../shared/anchors/compare.sh}
M="${BUILD_DIR:-$ROOT/build}/madsfm"
[ -x "$M" ] || { echo "build madsfm first (bash scripts/build.sh)" >&2; exit 2; }
[ -f "$COMPARE" ] || { echo "compare.sh not found at $COMPARE (set COMPARE=)" >&2; exit 2; }
: "${ANCHORS_DIR:?set ANCHORS_DIR to the folder the anchors build.sh wrote}"
PRESETS=${PRESETS:-$("$M" synth --help 2>&1 | grep -o 'hard_[a-z_]*' | sort -u | tr '\n' ' ')}
mkdir -p "$OUT"
echo "# $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(date -u '+%Y-%m-%d %H:%M UTC'), $N pairs per preset, seed $SEED"
for preset in $PRESETS; do
  case $preset in
    *two_focal) setting=twofocal ;; *shared_focal) setting=shared ;; *) setting=calib ;;
  esac
  dir="$OUT/sets/$preset"
  [ -f "$dir/pairs.txt" ] || "$M" synth --preset "$preset" --num_pairs "$N" --seed "$SEED" --output_path "$dir" 2>/dev/null
  echo "## $preset ($setting)"
  if [ "${THRESHOLDS:-paper}" = fixed ]; then export REPROJ=8 EPI=2; fi
  bash "$COMPARE" "$M" "$dir/pairs.txt" "$setting" "$OUT/runs/$preset"
  echo
done
