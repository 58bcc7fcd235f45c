#!/usr/bin/env python3
"""Ground truth of a Strecha et al. (2008) multi-view scene for `madsfm model_compare`.

The scenes (fountain-P11, Herz-Jesu-P8/P25, entry-P10, castle-P19/P30; 3072 x 2048 photos) are public, e.g. in
github.com/openMVG/SfM_quality_evaluation under Benchmarking_Camera_Calibration_2008/<scene>/. Each image
<name> has gt_dense_cameras/<name>.camera: K (3 rows), a row of radial distortion, R (3 rows; camera-to-world
rotation), the camera centre C, and the image size. World to camera is then x_cam = R^T (x - C), so R_gt = R^T
and t_gt = -R^T C; f is the mean of K's fx and fy.

Usage: strecha_ground_truth.py CAMERA_DIR IMAGE_DIR > ground_truth.json
Only images present in IMAGE_DIR with a .camera file are written.
"""
import json
import os
import sys


def read_camera(path):
    rows = [[float(v) for v in line.split()] for line in open(path) if line.strip()]
    if len(rows) < 9 or any(len(r) != 3 for r in rows[:8]):
        sys.exit(f"strecha_ground_truth.py: '{path}' is not a Strecha .camera file")
    K, R, C = rows[0:3], rows[4:7], rows[7]
    Rt = [[R[c][r] for c in range(3)] for r in range(3)]
    t = [-sum(Rt[r][c] * C[c] for c in range(3)) for r in range(3)]
    return {"R": [v for row in Rt for v in row], "t": t, "f": 0.5 * (K[0][0] + K[1][1])}


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    cam_dir, image_dir = sys.argv[1:]
    images = []
    for name in sorted(os.listdir(image_dir)):
        cam = os.path.join(cam_dir, name + ".camera")
        if os.path.isfile(cam):
            images.append({"name": name, **read_camera(cam)})
    if not images:
        sys.exit(f"strecha_ground_truth.py: no image of '{image_dir}' has a .camera file in '{cam_dir}'")
    json.dump({"images": images}, sys.stdout, indent=1)


if __name__ == "__main__":
    main()
