#!/usr/bin/env bash
# The rendered multi-view demo (issue 5): renders a scene with an unknown focal length and monocular-depth-like
# priors, runs COLMAP's SIFT extraction + exhaustive matching, then `madsfm mapper` and plain `colmap mapper` on
# copies of the same database, and prints both against the ground truth.
# Usage: scene_demo.sh MADSFM_BINARY WORK_DIR [NUM_IMAGES] [SEED]   (exit 1 if an assertion fails with CHECK=1)
set -euo pipefail
MADSFM="$1"; WORK="$2"; NUM_IMAGES="${3:-10}"; SEED="${4:-0}"
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
command -v colmap >/dev/null || { echo "SKIP: colmap binary not found"; exit 77; }
export QT_QPA_PLATFORM=offscreen
rm -rf "$WORK"; mkdir -p "$WORK"
t0=$(date +%s.%N)
"$MADSFM" render_scene --output_path "$WORK/scene" --num_images "$NUM_IMAGES" --seed "$SEED" >/dev/null
t1=$(date +%s.%N)
bash "$HERE/colmap_features.sh" "$WORK/scene"
t2=$(date +%s.%N)
cp "$WORK/scene/database.db" "$WORK/madsfm.db"
cp "$WORK/scene/database.db" "$WORK/colmap.db"
s0=$(date +%s.%N)
"$MADSFM" mapper --database_path "$WORK/madsfm.db" --image_path "$WORK/scene/images" --depth_path "$WORK/scene/depths" \
  --output_path "$WORK/madsfm" > "$WORK/madsfm_mapper.log" 2>&1 || { cat "$WORK/madsfm_mapper.log"; exit 1; }
s1=$(date +%s.%N)
mkdir -p "$WORK/colmap"
colmap mapper --database_path "$WORK/colmap.db" --image_path "$WORK/scene/images" --output_path "$WORK/colmap" \
  > "$WORK/colmap_mapper.log" 2>&1 || { tail -20 "$WORK/colmap_mapper.log"; exit 1; }
s2=$(date +%s.%N)
# colmap mapper writes one folder per model; take the largest.
best=""; bestn=-1
for d in "$WORK"/colmap/*/; do
  n=$("$MADSFM" model_compare --input_path "$d" --ground_truth_path "$WORK/scene/ground_truth.json" --output_format json \
      | python3 -c 'import json,sys; print(json.load(sys.stdin)["num_registered"])')
  if [ "$n" -gt "$bestn" ]; then best="$d"; bestn=$n; fi
done
"$MADSFM" model_compare --input_path "$WORK/madsfm/0" --ground_truth_path "$WORK/scene/ground_truth.json" \
  --output_format json > "$WORK/madsfm.json"
"$MADSFM" model_compare --input_path "$best" --ground_truth_path "$WORK/scene/ground_truth.json" \
  --output_format json > "$WORK/colmap.json"
grep -E "^\[|camera" "$WORK/madsfm_mapper.log" | sed 's/^/  /'
python3 - "$WORK/madsfm.json" "$WORK/colmap.json" "$t0" "$t1" "$t2" "$s0" "$s1" "$s2" "${CHECK:-0}" <<'PY'
import json, sys
m, c = (json.load(open(p)) for p in sys.argv[1:3])
t0, t1, t2, s0, s1, s2 = (float(x) for x in sys.argv[3:9])
tm, tc, trender, tfeat, check = s1 - s0, s2 - s1, t1 - t0, t2 - t1, sys.argv[9] == "1"
print(f"scene rendered in {trender:.1f} s; COLMAP SIFT extraction + exhaustive matching {tfeat:.1f} s")
print(f"| method | registered / {m['num_gt_images']} | median rot err (deg) | max rot err (deg) | median focal err | reproj err (px) | time (s) |")
print("|---|---|---|---|---|---|---|")
for name, d, t in (("madsfm mapper", m, tm), ("colmap mapper", c, tc)):
    print(f"| {name} | {d['num_registered']} | {d['median_rot_err_deg']:.3f} | {d['max_rot_err_deg']:.3f} | "
          f"{100*d['median_focal_err']:.2f}% | {d['mean_reproj_error']:.3f} | {t:.1f} |")
if check:
    ok = True
    def req(cond, what):
        global ok
        print(("ok:   " if cond else "FAIL: ") + what); ok &= cond
    req(m['num_registered'] >= c['num_registered'], "madsfm registers at least as many images as colmap")
    req(m['num_registered'] >= 0.8 * m['num_gt_images'], "madsfm registers >= 80% of the images")
    req(m['median_focal_err'] <= 0.02, "madsfm median focal error <= 2%")
    req(m['median_rot_err_deg'] <= c['median_rot_err_deg'] + 0.05, "madsfm median rotation error <= colmap's (+0.05 deg)")
    sys.exit(0 if ok else 1)
PY
