#!/usr/bin/env bash
# Plain `colmap mapper` against `madsfm mapper` on copies of the same database, several times over (COLMAP's
# matching and mapper vary between runs), scored against ground truth with `madsfm model_compare`.
#
# In: PROJECT_DIR/images/* and PROJECT_DIR/ground_truth.json (world->camera R, t and f per image name, the format
# of `madsfm model_compare --help`). Per run k: PROJECT_DIR/run<k>/ gets COLMAP SIFT + exhaustive matching
# (scripts/e2e/colmap_features.sh; its SINGLE_CAMERA and MAX_IMAGE_SIZE environment variables apply), then both
# mappers. Prints one markdown row per run: registered images, median rotation / translation-direction error over
# all pairs of registered images, median focal error, wall time.
# Usage: scripts/e2e/mapper_ab.sh MADSFM_BINARY PROJECT_DIR [RUNS (default 4)] [madsfm mapper options...]
set -uo pipefail
W="$1"; P="$2"; RUNS="${3:-4}"; shift $(( $# < 3 ? $# : 3 ))
S="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export QT_QPA_PLATFORM=offscreen
for f in "$P/images" "$P/ground_truth.json"; do
  [ -e "$f" ] || { echo "$0: missing $f" >&2; exit 1; }
done
cmp() {  # cmp MODEL: "registered, rot, trans, focal" or "no model"
  "$W" model_compare --input_path "$1" --ground_truth_path "$P/ground_truth.json" --output_format json 2>/dev/null |
    /usr/bin/python3 -c "
import json, sys
try:
    d = json.load(sys.stdin)
    print('%d/%d, %.3f deg, %.2f deg, %.2f%%' % (d['num_registered'], d['num_gt_images'], d['median_rot_err_deg'],
          d['median_trans_err_deg'], 100 * d['median_focal_err']), end='')
except Exception:
    print('no model', end='')"; return 0
}
echo "| run | plain colmap mapper: registered, rot, trans dir, focal, time | madsfm mapper: registered, rot, trans dir, focal, time |"
echo "|---|---|---|"
for k in $(seq 1 "$RUNS"); do
  d="$P/run$k"
  rm -rf "$d"; mkdir -p "$d"; ln -s ../images "$d/images"
  bash "$S/colmap_features.sh" "$d" >/dev/null 2>&1 || { echo "run $k: colmap features failed (logs in $d/logs)"; continue; }
  cp "$d/database.db" "$d/plain.db"; cp "$d/database.db" "$d/madsfm.db"; mkdir -p "$d/plain"
  t0=$(date +%s.%N)
  colmap mapper --database_path "$d/plain.db" --image_path "$d/images" --output_path "$d/plain" >"$d/plain.log" 2>&1
  t1=$(date +%s.%N)
  "$W" mapper --database_path "$d/madsfm.db" --image_path "$d/images" --output_path "$d/madsfm" "$@" \
    >"$d/madsfm.log" 2>&1
  t2=$(date +%s.%N)
  # Plain COLMAP may write several models; the largest is scored (most registered images).
  plain=$(for m in "$d"/plain/*/; do [ -e "$m/images.bin" ] && echo "$(stat -c %s "$m/images.bin") $m"; done |
          sort -rn | head -1 | cut -d' ' -f2)
  printf '| %d | %s, %.1f s | %s, %.1f s |\n' "$k" "$([ -n "$plain" ] && cmp "$plain" || echo "no model")" \
    "$(echo "$t1 - $t0" | bc)" "$(cmp "$d/madsfm/0")" "$(echo "$t2 - $t1" | bc)"
done
