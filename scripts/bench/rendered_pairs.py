#!/usr/bin/env python3
"""Pair directories from a rendered COLMAP project: a second, independent source of test pairs for the estimator.

`madsfm synth` draws keypoints, matches and outliers from one analytic model. This script takes instead a project
written by `madsfm render_scene` and matched by `scripts/e2e/colmap_features.sh`: real SIFT keypoints on
ray-traced images, COLMAP's raw (unverified) matches with whatever outliers the matcher made, the depth priors of
the renderer (own scale and shift per image, smooth distortion, half resolution), and the true cameras. Every
image pair with at least --min_matches raw matches becomes one pair directory (docs/formats.md, "Pair
directories"): info.json with the true K0, K1, T_0to1 and image sizes, matches_0.npy / matches_1.npy (pixel
coordinates of the raw matches), depth_0.npy / depth_1.npy (the priors), gt_depth_0.npy / gt_depth_1.npy (the
exact depths, 0 = sky, for bench's depth-correction metrics). A pairs.txt lists them.

--keypoint_noise SIGMA adds Gaussian noise of SIGMA pixels per axis to every keypoint of an image (the same for all
pairs that share it, drawn from a seed made of the prefix and the image name): ray-traced SIFT keypoints are about
0.05 px precise (1.4826 x the median Sampson error at the true pose), real matches 0.3-1 px (0.59 px on the ETH3D
example pair).

Usage: rendered_pairs.py PROJECT_DIR OUT_DIR [--min_matches 30] [--prefix NAME] [--keypoint_noise SIGMA]
       (PROJECT_DIR holds database.db, depths/, ground_truth.json). Run `madsfm bench` or
       ../shared/anchors/compare.sh on OUT_DIR/pairs.txt.
"""
import argparse
import json
import os
import shutil
import sqlite3
import sys
import zlib

import numpy as np

MAX_IMAGE_ID = 2147483647


def pair_id_to_images(pair_id):
    return pair_id // MAX_IMAGE_ID, pair_id % MAX_IMAGE_ID


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("project")
    ap.add_argument("out")
    ap.add_argument("--min_matches", type=int, default=30)
    ap.add_argument("--prefix", default="")
    ap.add_argument("--keypoint_noise", type=float, default=0.0)
    args = ap.parse_args()
    db_path = os.path.join(args.project, "database.db")
    gt_path = os.path.join(args.project, "ground_truth.json")
    for p in (db_path, gt_path):
        if not os.path.isfile(p):
            sys.exit(f"rendered_pairs.py: '{p}' not found (render_scene + colmap_features.sh first)")
    gt = {im["name"]: im for im in json.load(open(gt_path))["images"]}
    db = sqlite3.connect(f"file:{db_path}?mode=ro", uri=True)
    names = dict(db.execute("SELECT image_id, name FROM images"))
    keypoints = {}
    for image_id, rows, cols, data in db.execute("SELECT image_id, rows, cols, data FROM keypoints"):
        keypoints[image_id] = np.frombuffer(data, np.float32).reshape(rows, cols)[:, :2].astype(np.float64)
        if args.keypoint_noise > 0.0:
            seed = zlib.crc32((args.prefix + names[image_id]).encode())
            keypoints[image_id] += np.random.default_rng(seed).normal(0.0, args.keypoint_noise, (rows, 2))
    os.makedirs(args.out, exist_ok=True)
    listed = []
    for pair_id, rows, data in db.execute("SELECT pair_id, rows, data FROM matches WHERE rows > 0 ORDER BY pair_id"):
        if rows < args.min_matches:
            continue
        i0, i1 = pair_id_to_images(pair_id)
        n0, n1 = names[i0], names[i1]
        g0, g1 = gt[n0], gt[n1]
        m = np.frombuffer(data, np.uint32).reshape(rows, 2)
        R0, R1 = np.array(g0["R"]).reshape(3, 3), np.array(g1["R"]).reshape(3, 3)
        t0, t1 = np.array(g0["t"]), np.array(g1["t"])
        R = R1 @ R0.T
        T = np.eye(4)
        T[:3, :3] = R
        T[:3, 3] = t1 - R @ t0
        name = f"{args.prefix}{os.path.splitext(n0)[0]}_{os.path.splitext(n1)[0]}"
        d = os.path.join(args.out, name)
        os.makedirs(d, exist_ok=True)
        np.save(os.path.join(d, "matches_0.npy"), keypoints[i0][m[:, 0]])
        np.save(os.path.join(d, "matches_1.npy"), keypoints[i1][m[:, 1]])
        for k, n in ((0, n0), (1, n1)):
            shutil.copyfile(os.path.join(args.project, "depths", n + ".npy"), os.path.join(d, f"depth_{k}.npy"))
            shutil.copyfile(os.path.join(args.project, "true_depths", n + ".npy"), os.path.join(d, f"gt_depth_{k}.npy"))

        def K(g):
            return [[g["f"], 0.0, g["cx"]], [0.0, g["f"], g["cy"]], [0.0, 0.0, 1.0]]

        info = {
            "K0": K(g0), "K1": K(g1), "T_0to1": T.tolist(),
            "matches_0_file": "matches_0.npy", "matches_1_file": "matches_1.npy",
            "depth_0_file": "depth_0.npy", "depth_1_file": "depth_1.npy",
            "gt_depth_0_file": "gt_depth_0.npy", "gt_depth_1_file": "gt_depth_1.npy",
            "image_size_0": [g0["width"], g0["height"]], "image_size_1": [g1["width"], g1["height"]],
            "source": {"project": os.path.abspath(args.project), "image0": n0, "image1": n1},
        }
        with open(os.path.join(d, "info.json"), "w") as f:
            json.dump(info, f, indent=1)
        listed.append(name)
    # Appended (several projects may share OUT_DIR), each pair once.
    list_path = os.path.join(args.out, "pairs.txt")
    known = set(open(list_path).read().split()) if os.path.isfile(list_path) else set()
    with open(list_path, "a") as f:
        for name in listed:
            if name not in known:
                f.write(name + "\n")
    print(f"rendered_pairs.py: {len(listed)} pairs from {args.project} -> {args.out}")


if __name__ == "__main__":
    main()
