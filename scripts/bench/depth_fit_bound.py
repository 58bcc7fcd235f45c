#!/usr/bin/env python3
"""How well can the depth corrections be fitted at all from two views' geometry?  With the TRUE pose, triangulate
a set of matches and fit each view's prior to the triangulated depths (z ~ a d + b) with several weightings and
robust losses; count the pairs whose corrected priors come within 1.25x of the oracle (the best per-view affine
fit to the true depths), on the metric of `madsfm bench` (median relative error with one common scale for both
views, evaluated on bench's true inliers).  Two sets of matches are fitted:
  * "seen": the Sampson inliers of the true pose (EPI px, default 2) with priors in both views: what an estimator
    that found the exact pose would see.  No estimator knows more, so this is a practical bound.
  * "filtered": bench's true inliers themselves (the true depth lifted with the true pose lands within 2 px and
    5%): an optimistic bound, since that filter keeps the matches with the least noise along the epipolar line,
    which no estimator can tell apart.

usage: PYTHONPATH=build/python depth_fit_bound.py SET_DIR [SET_DIR ...]   (folders written by `madsfm synth`)
       Env: EPI (Sampson threshold of the "seen" set, px; default 2)
"""
import glob
import json
import os
import sys

import numpy as np

from madsfm import _madsfm


def relative_fit(d, z):
    """The oracle's fit: argmin sum(((a d + b) / z - 1)^2)."""
    a = np.stack([d / z, 1.0 / z], 1)
    return np.linalg.lstsq(a, np.ones(len(d)), rcond=None)[0]


def gauge_error(c0, c1, d0, d1, z0, z1):
    """bench's metric: median |g (a d + b) / z - 1| over both views with the least-squares common scale g."""
    r = np.concatenate([(c0[0] * d0 + c0[1]) / z0, (c1[0] * d1 + c1[1]) / z1])
    g = r.sum() / (r * r).sum()
    return float(np.median(np.abs(g * r - 1.0)))


def triangulate(R, t, n0, n1):
    """Depths z0, z1 with z1 n1 ~ R z0 n0 + t (least squares over the two rays) and sin^2 of the ray angle."""
    a = (R @ n0.T).T
    a11, a12, a22 = (a * a).sum(1), -(a * n1).sum(1), (n1 * n1).sum(1)
    b1, b2 = -(a @ t), n1 @ t
    det = a11 * a22 - a12 * a12
    z0 = (b1 * a22 - a12 * b2) / det
    z1 = (a11 * b2 - a12 * b1) / det
    sin2 = np.linalg.norm(np.cross(a, n1), axis=1) ** 2 / (a11 * a22)
    return z0, z1, sin2


def weighted_fit(d, z, w, loss, rounds=10):
    """z ~ a d + b with relative-residual weights w and IRLS under `loss` (none, huber, cauchy)."""
    robust = np.ones(len(d))
    for _ in range(rounds):
        ww = w * robust / (z * z)
        a, b = np.linalg.lstsq(np.stack([d, np.ones(len(d))], 1) * np.sqrt(ww)[:, None], z * np.sqrt(ww),
                               rcond=None)[0]
        if loss == "none":
            break
        rel = np.abs(a * d + b - z) / z * np.sqrt(w)
        s = 1.4826 * np.median(rel)
        if not s > 0:
            break
        if loss == "huber":
            c = 1.345 * s
            robust = np.where(rel <= c, 1.0, c / np.maximum(rel, 1e-300))
        else:
            robust = 1.0 / (1.0 + (rel / (2.385 * s)) ** 2)
    return a, b


def pair_bound(path):
    info = json.load(open(os.path.join(path, "info.json")))
    load = lambda key: np.load(os.path.join(path, info[key]))
    p0, p1 = load("matches_0_file").astype(float), load("matches_1_file").astype(float)
    K0, K1, T = np.array(info["K0"]), np.array(info["K1"]), np.array(info["T_0to1"])
    (w0, h0), (w1, h1) = info["image_size_0"], info["image_size_1"]
    sample = lambda key, p, w, h: _madsfm._sample_depth(load(key).astype(float), p, w, h, key)
    d0, d1 = sample("depth_0_file", p0, w0, h0), sample("depth_1_file", p1, w1, h1)
    z0, z1 = sample("gt_depth_0_file", p0, w0, h0), sample("gt_depth_1_file", p1, w1, h1)
    n0 = (np.linalg.inv(K0) @ np.c_[p0, np.ones(len(p0))].T).T
    n1 = (np.linalg.inv(K1) @ np.c_[p1, np.ones(len(p1))].T).T
    # bench's true inliers: the true depth at p0 lifted with the true pose lands within 2 px of p1 and within 5% of
    # the true depth at p1.
    with np.errstate(invalid="ignore"):
        X1 = (T[:3, :3] @ (z0[:, None] * n0).T).T + T[:3, 3]
        proj = (K1 @ X1.T).T
        use = ((d0 > 0) & (d1 > 0) & (z0 > 0) & (z1 > 0) & (X1[:, 2] > 0) & (np.abs(X1[:, 2] - z1) <= 0.05 * z1)
               & (np.linalg.norm(proj[:, :2] / proj[:, 2:3] - p1, axis=1) < 2.0))
    if use.sum() < 8:
        return None
    # The Sampson inliers of the true pose, in pixels.
    t = T[:3, 3] / np.linalg.norm(T[:3, 3])
    tx = np.array([[0, -t[2], t[1]], [t[2], 0, -t[0]], [-t[1], t[0], 0]])
    F = np.linalg.inv(K1).T @ tx @ T[:3, :3] @ np.linalg.inv(K0)
    x0, x1 = np.c_[p0, np.ones(len(p0))], np.c_[p1, np.ones(len(p1))]
    Fx0, Ftx1 = (F @ x0.T).T, (F.T @ x1.T).T
    sampson = (x1 * Fx0).sum(1) ** 2 / (Fx0[:, 0] ** 2 + Fx0[:, 1] ** 2 + Ftx1[:, 0] ** 2 + Ftx1[:, 1] ** 2)
    epi = float(os.environ.get("EPI", "2"))
    seen = (sampson <= epi * epi) & (d0 > 0) & (d1 > 0)
    e0, e1, ez0, ez1 = d0[use], d1[use], z0[use], z1[use]  # the evaluation set
    o0, o1 = relative_fit(e0, ez0), relative_fit(e1, ez1)
    oracle = float(np.median(np.abs(np.concatenate([(o0[0] * e0 + o0[1]) / ez0, (o1[0] * e1 + o1[1]) / ez1]) - 1)))
    angular_noise = 1.0 / K0[0, 0]
    ratios = {}
    for name, subset in (("seen", seen), ("filtered", use)):
        tz0, tz1, sin2 = triangulate(T[:3, :3], t, n0[subset], n1[subset])
        ok = (tz0 > 0) & (tz1 > 0)
        f0, f1 = d0[subset][ok], d1[subset][ok]
        for loss in ("none", "huber", "cauchy"):
            for prior_sigma in (0.03, 0.1):
                if ok.sum() < 8:  # too few matches in front of both cameras: no fit
                    ratios[f"{name}:{loss}/{prior_sigma}"] = float("inf")
                    continue
                w = 1.0 / (prior_sigma ** 2 + angular_noise ** 2 / np.maximum(sin2[ok], 1e-300))
                c0 = weighted_fit(f0, tz0[ok], w, loss)
                c1 = weighted_fit(f1, tz1[ok], w, loss)
                ratios[f"{name}:{loss}/{prior_sigma}"] = gauge_error(c0, c1, e0, e1, ez0, ez1) / oracle
    return ratios


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for set_dir in sys.argv[1:]:
        results = [r for r in (pair_bound(p) for p in sorted(glob.glob(os.path.join(set_dir, "*/")))) if r]
        if not results:
            print(f"{set_dir}: no pairs with ground truth")
            continue
        n = len(results)
        cells = []
        for name in ("seen", "filtered"):
            keys = [k for k in results[0] if k.startswith(name + ":")]
            per_fit = {k: sum(r[k] <= 1.25 for r in results) for k in keys}
            best_key = max(per_fit, key=per_fit.get)
            best_any = sum(min(r[k] for k in keys) <= 1.25 for r in results)
            cells.append(f"{name}: best fit ({best_key.split(':')[1]}) {100 * per_fit[best_key] / n:.0f}%, best of "
                         f"the six per pair {100 * best_any / n:.0f}%")
        print(f"{os.path.basename(os.path.normpath(set_dir))} ({n} pairs), within 1.25x of the oracle with the true "
              f"pose: " + "; ".join(cells))


if __name__ == "__main__":
    main()
