#!/usr/bin/env bash
# Plain colmap mapper with a relaxed initial pair (--Mapper.init_min_tri_angle, default 1 deg) on the folders that
# tests/e2e/hard_scene_mapper.sh leaves (scene/ with database.db, images/, ground_truth.json): the time and outcome
# plain COLMAP reaches on a low-parallax scene when a user lowers its 16 deg initial-pair angle by hand, beside
# madsfm mapper's row of the same folder (docs/benchmarks.md section 9).
# Usage: scripts/e2e/plain_relaxed.sh MADSFM_BINARY WORK_DIR [WORK_DIR ...]   Env: INIT_MIN_TRI_ANGLE (default 1)
set -euo pipefail
MADSFM="$1"; shift
export QT_QPA_PLATFORM=offscreen
angle=${INIT_MIN_TRI_ANGLE:-1}
echo "| scene folder | plain, init_min_tri_angle $angle: registered | rot err (deg) | focal err | time (s) | madsfm: registered | rot err (deg) | focal err | time (s) |"
echo "|---|---|---|---|---|---|---|---|---|"
for work in "$@"; do
  for f in scene/database.db scene/ground_truth.json madsfm.json madsfm_mapper.log; do
    [ -f "$work/$f" ] || { echo "$work: no $f (run tests/e2e/hard_scene_mapper.sh on it first)" >&2; exit 2; }
  done
  out="$work/plain_relaxed"; rm -rf "$out"; mkdir -p "$out/model"
  cp "$work/scene/database.db" "$out/database.db"
  t0=$(date +%s.%N)
  colmap mapper --database_path "$out/database.db" --image_path "$work/scene/images" --output_path "$out/model" \
    --Mapper.init_min_tri_angle "$angle" > "$out/colmap_mapper.log" 2>&1 || true
  t1=$(date +%s.%N)
  best='{"num_registered": 0}'; bestn=-1
  for d in "$out"/model/*/; do
    [ -d "$d" ] || continue
    j=$("$MADSFM" model_compare --input_path "$d" --ground_truth_path "$work/scene/ground_truth.json" \
          --output_format json 2>/dev/null) || continue
    n=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["num_registered"])' "$j")
    if [ "$n" -gt "$bestn" ]; then best=$j; bestn=$n; fi
  done
  echo "$best" > "$out/compare.json"
  python3 - "$out/compare.json" "$work/madsfm.json" "$work/madsfm_mapper.log" "$work" "$t0" "$t1" <<'PY'
import json, re, sys
p, m = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
total = re.search(r"total ([0-9.]+) s", open(sys.argv[3]).read())
n = m.get("num_gt_images", "?")
cell = lambda r, k, f: f(r[k]) if k in r else "-"
deg = lambda v: f"{v:.3f}"
pct = lambda v: f"{100 * v:.2f}%"
print(f"| {sys.argv[4]} | {p['num_registered']}/{n} | {cell(p, 'median_rot_err_deg', deg)} | "
      f"{cell(p, 'median_focal_err', pct)} | {float(sys.argv[6]) - float(sys.argv[5]):.1f} | {m['num_registered']}/{n} | "
      f"{cell(m, 'median_rot_err_deg', deg)} | {cell(m, 'median_focal_err', pct)} | {total.group(1) if total else '-'} |")
PY
done
