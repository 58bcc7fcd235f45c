#!/usr/bin/env bash
# COLMAP features for an end-to-end demo project: SIFT extraction and exhaustive matching on the CPU.
#
# Usage: scripts/e2e/colmap_features.sh PROJECT_DIR
# In:  PROJECT_DIR/images/*  (e.g. written by `madsfm render_scene --output_path PROJECT_DIR`).
# Out: PROJECT_DIR/database.db (replaced) with one shared SIMPLE_RADIAL camera (no EXIF, so COLMAP guesses
#      f = 1.2 max(W, H) and stores prior_focal_length = 0; SINGLE_CAMERA=0: one such camera per image),
#      keypoints, descriptors, matches and verified two-view geometries; logs in PROJECT_DIR/logs/. Quiet on
#      success; on failure prints the log and exits 1.
#
# Headless (checked with COLMAP 3.8, /usr/bin/colmap, Debian build without CUDA, no X server): SIFT on the GPU
# (the default --SiftExtraction.use_gpu 1 / --SiftMatching.use_gpu 1) needs a Qt application and an OpenGL
# context and aborts (SIGABRT) without a display: "could not connect to display" from Qt's xcb plugin, or with
# QT_QPA_PLATFORM=offscreen "Check failed: context_.create()" in opengl_utils.cc. With use_gpu 0 (CPU SIFT,
# VLFeat) neither command creates a Qt application or a GL context, so no display, Xvfb or GPU is needed.
# QT_QPA_PLATFORM=offscreen is exported as well, so that no Qt code path tries to reach an X server.
# Environment: COLMAP (binary, default colmap), NUM_THREADS (default -1 = all cores), SINGLE_CAMERA (default 1),
# MAX_IMAGE_SIZE (default 3200, COLMAP's: SIFT runs on images downscaled to it; keypoints stay in full-size pixels).
set -euo pipefail

if [[ $# -ne 1 ]]; then
  echo "usage: $0 PROJECT_DIR" >&2
  exit 2
fi
PROJECT_DIR=$1
COLMAP=${COLMAP:-colmap}
NUM_THREADS=${NUM_THREADS:--1}
SINGLE_CAMERA=${SINGLE_CAMERA:-1}
MAX_IMAGE_SIZE=${MAX_IMAGE_SIZE:-3200}
export QT_QPA_PLATFORM=offscreen

if [[ ! -d "$PROJECT_DIR/images" ]]; then
  echo "$0: no images directory '$PROJECT_DIR/images'" >&2
  exit 1
fi
mkdir -p "$PROJECT_DIR/logs"
rm -f "$PROJECT_DIR/database.db" "$PROJECT_DIR/database.db-shm" "$PROJECT_DIR/database.db-wal"

run() {  # run LOG_NAME COMMAND...: quiet unless it fails
  local log="$PROJECT_DIR/logs/$1.log"
  shift
  if ! "$@" >"$log" 2>&1; then
    echo "$0: '$*' failed; log $log:" >&2
    cat "$log" >&2
    exit 1
  fi
}

run feature_extractor "$COLMAP" feature_extractor \
  --database_path "$PROJECT_DIR/database.db" \
  --image_path "$PROJECT_DIR/images" \
  --ImageReader.single_camera "$SINGLE_CAMERA" \
  --ImageReader.camera_model SIMPLE_RADIAL \
  --SiftExtraction.use_gpu 0 \
  --SiftExtraction.max_image_size "$MAX_IMAGE_SIZE" \
  --SiftExtraction.num_threads "$NUM_THREADS"

run exhaustive_matcher "$COLMAP" exhaustive_matcher \
  --database_path "$PROJECT_DIR/database.db" \
  --SiftMatching.use_gpu 0 \
  --SiftMatching.num_threads "$NUM_THREADS"
