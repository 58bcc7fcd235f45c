#!/usr/bin/env bash
# madsfm mapper's fallbacks (issue 14), forced with a stand-in colmap that fails chosen runs and forwards the others
# to the real colmap, on the real 2_2d3ds pair (COLMAP's own geometric verification first, so the database has
# COLMAP's rows, then madsfm's):
#   A. the seeded run fails        -> exit 0, the 'unseeded' model is kept;
#   B. every run on madsfm's rows fails -> exit 0, the 'colmap_rows' model (a restored copy) is kept, and the
#      database itself still holds madsfm's results;
#   C. every run fails             -> exit 1, the error names the logs;
# and every colmap mapper run gets the --Mapper.* options given to madsfm mapper.
# Usage: mapper_fallback.sh MADSFM_BINARY EXAMPLE_PAIRS_DIR WORK_DIR
set -euo pipefail
MADSFM="$1"; PAIRS="$2"; WORK="$3"
command -v colmap >/dev/null || { echo "SKIP: colmap binary not found"; exit 77; }
export QT_QPA_PLATFORM=offscreen
rm -rf "$WORK"; mkdir -p "$WORK"
"$MADSFM" import_pair --pair_path "$PAIRS/2_2d3ds" --output_path "$WORK/proj" >/dev/null
( cd "$WORK/proj" && colmap matches_importer --database_path database.db --match_list_path pairs.txt \
    --match_type pairs --SiftMatching.use_gpu 0 > matches_importer.log 2>&1 )
REAL=$(command -v colmap)
# stand-in: FAIL_IF=seeded|madsfm_rows|all; logs every call's arguments to $WORK/calls.txt
cat > "$WORK/colmap" <<SH
#!/usr/bin/env bash
echo "\$*" >> "$WORK/calls.txt"
args=" \$* "
case "\$FAIL_IF" in
  seeded) [[ "\$args" == *" --input_path "* ]] && { echo "stand-in: failing the seeded run"; exit 1; } ;;
  madsfm_rows) [[ "\$args" != *"colmap_rows.db"* ]] && { echo "stand-in: failing runs on madsfm's rows"; exit 1; } ;;
  all) echo "stand-in: failing every run"; exit 1 ;;
esac
exec "$REAL" "\$@"
SH
chmod +x "$WORK/colmap"
ok=1
check() { if eval "$1"; then echo "ok:   $2"; else echo "FAIL: $2"; ok=0; fi; }
count() { python3 -c 'import sqlite3,sys; print(sqlite3.connect(sys.argv[1]).execute(sys.argv[2]).fetchone()[0])' "$@"; }
run_case() {  # run_case NAME FAIL_IF: copies the project database, runs madsfm mapper; sets rc
  cp "$WORK/proj/database.db" "$WORK/$1.db"; : > "$WORK/calls.txt"
  set +e
  FAIL_IF=$2 "$MADSFM" mapper --database_path "$WORK/$1.db" --image_path "$WORK/proj/images" \
    --depth_path "$WORK/proj/depths" --output_path "$WORK/$1" --reproj_threshold 16 --epipolar_threshold 1 \
    --colmap_path "$WORK/colmap" --Mapper.ba_refine_principal_point 0 > "$WORK/$1.out" 2> "$WORK/$1.err"
  rc=$?
  set -e
  cp "$WORK/calls.txt" "$WORK/$1.calls"
  echo "--- case $1 (FAIL_IF=$2): exit $rc"; sed 's/^/  /' "$WORK/$1.out" "$WORK/$1.err"
}
registered() { "$MADSFM" model_compare --input_path "$1" --ground_truth_path "$WORK/proj/ground_truth.json" \
  --output_format json | python3 -c 'import json,sys; print(json.load(sys.stdin)["num_registered"])'; }

run_case A seeded
check '[ $rc -eq 0 ]' "A: exit 0 although the seeded run failed"
check 'grep -q "keeping the model of the .unseeded. run" "$WORK/A.err"' "A: stderr says the unseeded model is kept"
check '[ "$(registered "$WORK/A/0")" -eq 2 ]' "A: OUT/0 registers both images"
check '[ "$(grep -c " --input_path " "$WORK/A.calls")" -eq 1 ]' "A: one seeded run"
check '[ "$(grep -c . "$WORK/A.calls")" -eq "$(grep -c -- "--Mapper.ba_refine_principal_point 0" "$WORK/A.calls")" ]' \
  "A: every colmap mapper run got the --Mapper.* option"

run_case B madsfm_rows
check '[ $rc -eq 0 ]' "B: exit 0 although every run on madsfm's rows failed"
check 'grep -q "keeping the model of the .colmap_rows. run" "$WORK/B.err"' "B: stderr says the colmap_rows model is kept"
check 'grep -q "init_min_tri_angle" "$WORK/B.calls"' "B: a relaxed unseeded run was tried"
check '[ "$(registered "$WORK/B/0")" -eq 2 ]' "B: OUT/0 registers both images"
check '[ "$(count "$WORK/B.db" "SELECT count(*) FROM madsfm_two_view_geometries")" -gt 0 ]' \
  "B: the database still holds madsfm's results"
check '[ "$(count "$WORK/B/colmap_rows.db" "SELECT count(*) FROM sqlite_master WHERE name LIKE '"'"'madsfm%'"'"'")" -eq 0 ]' \
  "B: the copy has COLMAP's rows only"

run_case C all
check '[ $rc -eq 1 ]' "C: exit 1 when every colmap mapper run fails"
check 'grep -q "no colmap mapper run produced a model" "$WORK/C.err" && grep -q "colmap_mapper_colmap_rows.log" "$WORK/C.err"' \
  "C: the error says so and names the logs"
[ $ok -eq 1 ]
