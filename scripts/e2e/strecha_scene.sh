#!/usr/bin/env bash
# Real photos with ground-truth cameras and no depth against plain colmap mapper (issue 14): one scene of Strecha et
# al. (2008), e.g. Benchmarking_Camera_Calibration_2008/castle-P19 of github.com/openMVG/SfM_quality_evaluation
# (SCENE_DIR/images/*.jpg, 3072 x 2048, and SCENE_DIR/gt_dense_cameras/*.camera). Without depth sidecars madsfm
# runs its point method on every pair and keeps COLMAP's focal priors.
#
# Writes WORK_DIR/images (the .jpg files) and WORK_DIR/ground_truth.json (scripts/e2e/strecha_ground_truth.py),
# then scripts/e2e/mapper_ab.sh prints one row per run. The photos have no EXIF focal: COLMAP starts from
# 1.2 x 3072 px (the truth is about 2760 px). SIFT on images downscaled to MAX_IMAGE_SIZE (default 1600);
# SINGLE_CAMERA=0 gives every image its own unknown camera (the default 1: one shared camera).
# Usage: scripts/e2e/strecha_scene.sh MADSFM_BINARY SCENE_DIR WORK_DIR [RUNS (default 2)] [madsfm mapper options...]
set -uo pipefail
W="$1"; SCENE="$2"; OUT="$3"; RUNS="${4:-2}"; shift $(( $# < 4 ? $# : 4 ))
S="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
for f in "$SCENE/images" "$SCENE/gt_dense_cameras"; do
  [ -d "$f" ] || { echo "$0: missing directory $f" >&2; exit 1; }
done
mkdir -p "$OUT/images"
cp "$SCENE"/images/*.jpg "$OUT/images/"
/usr/bin/python3 "$S/strecha_ground_truth.py" "$SCENE/gt_dense_cameras" "$OUT/images" > "$OUT/ground_truth.json" ||
  exit 1
MAX_IMAGE_SIZE=${MAX_IMAGE_SIZE:-1600} bash "$S/mapper_ab.sh" "$W" "$OUT" "$RUNS" "$@"
