#!/usr/bin/env bash
# A second source of estimator test pairs, independent of `madsfm synth`'s generator: rendered scenes with real
# SIFT matches (scripts/bench/rendered_pairs.py). Renders, per seed, seven scenes with `madsfm render_scene`
# (640 x 480; room on a 60-degree arc, street walk, sideways walk, hand-held, forward walk, and the arc and the
# street with one focal per image), runs COLMAP's CPU SIFT and exhaustive matching, and exports every image
# pair with >= 30 raw matches as a pair directory. Three lists, for ../shared/anchors/compare.sh:
#   OUT/calib.txt     every pair (true K0, K1)
#   OUT/shared.txt    the pairs of the one-focal scenes
#   OUT/twofocal.txt  the pairs of the per-image-focal scenes
# Half of the seeds use a stronger non-affine prior distortion (--prior_distortion 0.06 instead of 0.03).
# SCENE_SET=low_parallax renders instead five small-motion walks in the room (hand-held in a ball of 0.2% and 0.4%
# of the distance to the target, sideways 0.3% and 0.6%, forward 1%), one shared camera each: pairs whose
# parallax is a few times the SIFT noise (calib.txt and shared.txt list the same pairs; twofocal.txt stays empty).
# KEYPOINT_NOISE=SIGMA adds that much Gaussian noise (px per axis) to the keypoints (rendered_pairs.py
# --keypoint_noise): the rendered SIFT keypoints are about 0.05 px precise, real ones 0.3-1 px.
# Usage: scripts/bench/rendered_pair_set.sh MADSFM_BINARY OUT_DIR [SEEDS...]   (default seeds: 100 101)
set -euo pipefail
MADSFM="$1"; OUT="$2"; shift 2
SEEDS=("$@"); [ ${#SEEDS[@]} -gt 0 ] || SEEDS=(100 101)
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
PY=/usr/bin/python3  # Debian's interpreter, which has python3-numpy
mkdir -p "$OUT/projects" "$OUT/pairs"
: > "$OUT/calib.txt"; : > "$OUT/shared.txt"; : > "$OUT/twofocal.txt"
for seed in "${SEEDS[@]}"; do
  distortion=$([ $((seed % 2)) -eq 0 ] && echo 0.03 || echo 0.06)
  scene() {  # scene NAME LIST SINGLE_CAMERA RENDER_ARGS...
    local name=$1 list=$2 single=$3; shift 3
    local p="$OUT/projects/${name}_s$seed"
    if [ ! -f "$p/database.db" ]; then
      mkdir -p "$p"
      "$MADSFM" render_scene --output_path "$p" --seed "$seed" --prior_distortion "$distortion" "$@" \
        >"$p/render.log" 2>&1 || { echo "render_scene failed for $p:" >&2; cat "$p/render.log" >&2; exit 1; }
      SINGLE_CAMERA=$single bash "$HERE/../e2e/colmap_features.sh" "$p"
    fi
    rm -rf "$OUT/pairs/${name}_s$seed"
    "$PY" "$HERE/rendered_pairs.py" "$p" "$OUT/pairs/${name}_s$seed" --prefix "${name}_s${seed}_" \
      --keypoint_noise "${KEYPOINT_NOISE:-0}" >&2
    sed "s|^|pairs/${name}_s$seed/|" "$OUT/pairs/${name}_s$seed/pairs.txt" | tee -a "$OUT/calib.txt" >> "$OUT/$list.txt"
  }
  if [ "${SCENE_SET:-standard}" = low_parallax ]; then
    scene handheld_b002 shared 1 --num_images 6 --motion handheld --baseline_fraction 0.002
    scene handheld_b004 shared 1 --num_images 6 --motion handheld --baseline_fraction 0.004
    scene sideways_b003 shared 1 --num_images 6 --motion sideways --baseline_fraction 0.003
    scene sideways_b006 shared 1 --num_images 6 --motion sideways --baseline_fraction 0.006
    scene forward_b01 shared 1 --num_images 6 --motion forward --baseline_fraction 0.01
    continue
  fi
  scene arc shared 1 --num_images 10
  scene street shared 1 --scene street --num_images 10
  scene sideways shared 1 --num_images 8 --motion sideways --baseline_fraction 0.08
  scene handheld shared 1 --num_images 6 --motion handheld --baseline_fraction 0.06
  scene forward shared 1 --num_images 8 --motion forward --baseline_fraction 0.2
  scene arc_per_image twofocal 0 --num_images 10 --per_image_fov_min 50 --per_image_fov_max 100
  scene street_per_image twofocal 0 --scene street --num_images 10 --per_image_fov_min 50 --per_image_fov_max 100
done
wc -l "$OUT/calib.txt" "$OUT/shared.txt" "$OUT/twofocal.txt" >&2
