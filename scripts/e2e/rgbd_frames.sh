#!/usr/bin/env bash
# Real RGB-D frames with sensor depth against plain colmap mapper (issue 14): the five frames of Open3D's test data
# (examples/TestData/RGBD of Open3D before 0.15: color/0000N.jpg, depth/0000N.png as 16-bit millimetres,
# trajectory.log with the camera-to-world poses; ICL-NUIM living room with simulated sensor noise, 640 x 480,
# f = 525 px). Any folder of that layout works (FOCAL= sets the true focal).
#
# Writes WORK_DIR/images and WORK_DIR/ground_truth.json, then scripts/e2e/mapper_ab.sh runs COLMAP SIFT + exhaustive
# matching (one shared camera, no focal prior), plain `colmap mapper` and `madsfm mapper --depth_path DATA/depth` (the
# 16-bit PNGs as they are) on copies of the same database; one line per run: registered images, median rotation /
# translation-direction error over all pairs, focal error, time. COLMAP's matching varies between runs, hence several.
# Usage: scripts/e2e/rgbd_frames.sh MADSFM_BINARY DATA_DIR WORK_DIR [RUNS (default 4)] [madsfm mapper options...]
set -uo pipefail
W="$1"; DATA="$2"; OUT="$3"; RUNS="${4:-4}"; shift $(( $# < 4 ? $# : 4 ))
S="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export QT_QPA_PLATFORM=offscreen
for f in "$DATA/color" "$DATA/depth" "$DATA/trajectory.log"; do
  [ -e "$f" ] || { echo "$0: missing $f" >&2; exit 1; }
done
mkdir -p "$OUT/images"
cp "$DATA"/color/* "$OUT/images/"
# trajectory.log: per frame a line "i i+1 n" then the 4 x 4 camera-to-world matrix; ground truth is x_cam = R x + t.
/usr/bin/python3 - "$DATA/trajectory.log" "$OUT/images" "${FOCAL:-525}" > "$OUT/ground_truth.json" <<'EOF'
import json, os, sys
rows = [l.split() for l in open(sys.argv[1]) if l.strip()]
names = sorted(os.listdir(sys.argv[2]))
images = []
for k, name in enumerate(names):
    T = [[float(v) for v in rows[5 * k + 1 + r]] for r in range(3)]
    R = [[T[c][r] for c in range(3)] for r in range(3)]  # R_wc^T
    t = [-sum(R[r][c] * T[c][3] for c in range(3)) for r in range(3)]
    images.append({"name": name, "R": [v for row in R for v in row], "t": t, "f": float(sys.argv[3])})
print(json.dumps({"images": images}, indent=1))
EOF
bash "$S/mapper_ab.sh" "$W" "$OUT" "$RUNS" --depth_path "$DATA/depth" "$@"
