#!/usr/bin/env bash
# `madsfm mapper --fix_focal_ba_uncertain 1` against 0 (and plain colmap mapper) on the same databases: per render
# seed, a hand-held sequence, a sideways walk and an orbit (one shared camera) are rendered and matched once, and the
# three mappers run on copies. One line per scene: registered images, median rotation error, median focal error,
# and how often the rule / the low-parallax rule fired.
# Usage: scripts/e2e/focal_fix_ab.sh MADSFM_BINARY WORK_DIR [SEEDS...]   (default seeds: 1 2 3)
set -uo pipefail
W="$1"; out="$2"; shift 2
SEEDS=("$@"); [ ${#SEEDS[@]} -gt 0 ] || SEEDS=(1 2 3)
S="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export QT_QPA_PLATFORM=offscreen
mkdir -p "$out"
cmp() {  # cmp MODEL_DIR GROUND_TRUTH: "registered rot focal" or "none"
  "$W" model_compare --input_path "$1" --ground_truth_path "$2" --output_format json 2>/dev/null | /usr/bin/python3 -c "
import json, sys
try:
    d = json.load(sys.stdin)
    print('%d %.4f deg %.3f%%' % (d['num_registered'], d['median_rot_err_deg'], 100 * d['median_focal_err']), end='')
except Exception:
    print('none', end='')"
}
scene() {  # scene NAME RENDER_ARGS...
  local name=$1; shift
  local d="$out/$name"
  rm -rf "$d"; mkdir -p "$d"
  "$W" render_scene --output_path "$d/scene" "$@" --image_width 480 --image_height 360 >/dev/null 2>&1 \
    || { echo "$name: render_scene failed"; return; }
  bash "$S/colmap_features.sh" "$d/scene" >/dev/null 2>&1 || { echo "$name: colmap features failed"; return; }
  cp "$d/scene/database.db" "$d/plain.db"; mkdir -p "$d/plain"
  colmap mapper --database_path "$d/plain.db" --image_path "$d/scene/images" --output_path "$d/plain" >/dev/null 2>&1
  local plain; plain=$(ls -d "$d"/plain/*/ 2>/dev/null | head -1)
  for v in 1 0; do
    cp "$d/scene/database.db" "$d/m$v.db"
    "$W" mapper --database_path "$d/m$v.db" --image_path "$d/scene/images" --depth_path "$d/scene/depths" \
      --output_path "$d/m$v" --fix_focal_ba_uncertain $v > "$d/m$v.log" 2>&1
  done
  echo "$name | plain $( [ -n "$plain" ] && cmp "$plain" "$d/scene/ground_truth.json" || echo none)" \
       "| rule on $(cmp "$d/m1/0" "$d/scene/ground_truth.json") | rule off $(cmp "$d/m0/0" "$d/scene/ground_truth.json")" \
       "| fired $(grep -c 'determines the focal' "$d/m1.log"), low parallax $(grep -c 'low parallax: bundle' "$d/m1.log")"
}
for s in "${SEEDS[@]}"; do
  scene "handheld_s$s" --num_images 5 --motion handheld --baseline_fraction 0.06 --seed "$s"
  scene "sideways_s$s" --num_images 8 --motion sideways --baseline_fraction 0.08 --seed "$s"
  scene "orbit_s$s" --num_images 8 --seed "$s"
done
