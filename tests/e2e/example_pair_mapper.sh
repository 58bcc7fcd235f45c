#!/usr/bin/env bash
# End-to-end on a real pair (tests/data/example_pairs/2_2d3ds: real photos, MASt3R matches imported as hloc
# would, MASt3R depth as sidecars, unknown focal lengths): `madsfm mapper` vs plain COLMAP (matches_importer
# geometric verification + colmap mapper). Asserts both register the pair and madsfm is at least as accurate,
# with focal errors under 10% (COLMAP's guess 1.2 max(W, H) is 40-50% off here).
# Usage: example_pair_mapper.sh MADSFM_BINARY EXAMPLE_PAIRS_DIR WORK_DIR
set -euo pipefail
MADSFM="$1"; PAIRS="$2"; WORK="$3"
command -v colmap >/dev/null || { echo "SKIP: colmap binary not found"; exit 77; }
export QT_QPA_PLATFORM=offscreen
rm -rf "$WORK"; mkdir -p "$WORK"
for variant in madsfm colmap; do
  "$MADSFM" import_pair --pair_path "$PAIRS/2_2d3ds" --output_path "$WORK/$variant" >/dev/null
done
"$MADSFM" mapper --database_path "$WORK/madsfm/database.db" --image_path "$WORK/madsfm/images" \
  --depth_path "$WORK/madsfm/depths" --output_path "$WORK/madsfm/sparse" --reproj_threshold 16 --epipolar_threshold 1
( cd "$WORK/colmap"
  colmap matches_importer --database_path database.db --match_list_path pairs.txt --match_type pairs \
    --SiftMatching.use_gpu 0 > matches_importer.log 2>&1
  mkdir -p sparse
  colmap mapper --database_path database.db --image_path images --output_path sparse > mapper.log 2>&1 )
"$MADSFM" model_compare --input_path "$WORK/madsfm/sparse/0" --ground_truth_path "$WORK/madsfm/ground_truth.json" \
  --output_format json > "$WORK/madsfm.json"
"$MADSFM" model_compare --input_path "$WORK/colmap/sparse/0" --ground_truth_path "$WORK/colmap/ground_truth.json" \
  --output_format json > "$WORK/colmap.json"
python3 - "$WORK/madsfm.json" "$WORK/colmap.json" <<'PY'
import json, sys
m, c = (json.load(open(p)) for p in sys.argv[1:3])
def get(d, *keys):
    for k in keys:
        if k in d: return d[k]
    raise KeyError(keys)
print("| | registered | rot err (deg) | focal err (max) |")
print("|---|---|---|---|")
for name, d in (("madsfm mapper", m), ("colmap mapper", c)):
    print(f"| {name} | {get(d,'num_registered')} | {get(d,'median_rot_err_deg'):.2f} | {100*get(d,'max_focal_err'):.1f}% |")
ok = True
def check(cond, what):
    global ok
    print(("ok:   " if cond else "FAIL: ") + what)
    ok &= cond
check(get(m,'num_registered') == 2, "madsfm registers both images")
check(get(c,'num_registered') == 2, "colmap registers both images")
check(get(m,'median_rot_err_deg') < 3.0, "madsfm rotation error < 3 deg")
check(get(m,'max_focal_err') < 0.10, "madsfm focal error < 10%")
check(get(m,'median_rot_err_deg') <= get(c,'median_rot_err_deg'), "madsfm rotation error <= colmap's")
check(get(m,'max_focal_err') <= get(c,'max_focal_err'), "madsfm focal error <= colmap's")
sys.exit(0 if ok else 1)
PY
