"""The public functions of the madsfm package: relative-pose estimation in the three camera modes, and depth maps."""

import errno
import os

import numpy as np

from . import _inputs, _madsfm

_SIZE_HINTS = ("give camera{i} as a dict with width and height, or image_size{i}=(width, height)")


def _estimate(camera_mode, kpts0, kpts1, depth0, depth1, camera0, camera1, options, method, image_size0,
              image_size1, max_image_dim):
    p0 = _inputs.keypoints(kpts0, "kpts0")
    p1 = _inputs.keypoints(kpts1, "kpts1")
    if p1.shape[0] != p0.shape[0]:
        raise ValueError(f"kpts1 has {p1.shape[0]} rows but kpts0 has {p0.shape[0]} (row i of kpts0 matches row i "
                         "of kpts1)")
    cam0 = _inputs.camera(camera0, "camera0", image_size0, "image_size0")
    cam1 = _inputs.camera(camera1, "camera1", image_size1, "image_size1")
    # Depth maps are sampled at the keypoints as observed (before any undistortion): the map is an image.
    d0 = _inputs.keypoint_depths(depth0, "depth0", p0, cam0.size, _SIZE_HINTS.format(i=0))
    d1 = _inputs.keypoint_depths(depth1, "depth1", p1, cam1.size, _SIZE_HINTS.format(i=1))
    opts = _inputs.options(options)
    if not isinstance(method, str):
        raise TypeError(f"method must be a str ({', '.join(_madsfm.METHODS)}), got {type(method).__name__}")

    calibrated = camera_mode == "calibrated"
    x0, intrinsics0 = cam0.estimator_inputs(p0, calibrated)
    x1, intrinsics1 = cam1.estimator_inputs(p1, calibrated)

    # As `madsfm pair`: a depth method with fewer than 4 matches with depth in both views runs the point method.
    num_with_depth = int(np.count_nonzero((d0 > 0) & (d1 > 0)))
    point_fallback = method != "points" and num_with_depth < 4
    notes = []
    if point_fallback:
        notes.append("no depth: point method" if depth0 is None or depth1 is None
                     else "fewer than 4 matches with valid depth in both views: point method")

    if max_image_dim is None:
        # Plausible focal lengths are [0.1, 10] x the largest image side (COLMAP's bounds); unknown sizes: no bounds.
        sides = [s for size in (cam0.size, cam1.size) if size for s in size]
        max_image_dim = float(max(sides)) if sides and not calibrated else 0.0
    elif calibrated:
        max_image_dim = 0.0
    return _madsfm._estimate(camera_mode, method, x0, x1, d0, d1, intrinsics0, intrinsics1, opts, point_fallback,
                             float(max_image_dim), notes)


def estimate_relative_pose(kpts0, kpts1, depth0, depth1, camera0, camera1, options=None, *, method="hybrid",
                           image_size0=None, image_size1=None):
    """Relative pose of two calibrated views from matched keypoints and monocular depth priors.

    kpts0, kpts1: N x 2 pixel coordinates of the matches (row i of kpts0 <-> row i of kpts1), pixel centres at
        integers (the upper-left pixel's centre is (0, 0)).
    depth0, depth1: per-keypoint depths (N,) (NaN: no depth), or whole depth maps (H, W) of any resolution with the
        image's aspect ratio, sampled bilinearly at the keypoints; None: no depth.
    camera0, camera1: COLMAP-style dicts {"model", "width", "height", "params"} (params in COLMAP's convention,
        pixel centres at +0.5; distorted models are undistorted) or pycolmap.Camera objects, or 3 x 3 matrices K
        in the keypoints' convention.
    options: madsfm.HybridEstimatorOptions or a dict of its fields; method: as `madsfm pair --method`.
    image_size0, image_size1: (width, height) when a camera is a matrix K and its depth is a map.

    Returns a madsfm.RelativePoseResult (X1 = R X0 + t; t in units of view 0's corrected depth d0 + shift0).
    Raises TypeError / ValueError naming the offending argument. Releases the GIL while estimating.
    """
    return _estimate("calibrated", kpts0, kpts1, depth0, depth1, camera0, camera1, options, method, image_size0,
                     image_size1, None)


def estimate_shared_focal_relative_pose(kpts0, kpts1, depth0, depth1, camera0, camera1, options=None, *,
                                        method="hybrid", image_size0=None, image_size1=None, max_image_dim=None):
    """As estimate_relative_pose, with one unknown focal length shared by both views (result.f0 == result.f1).

    Only the cameras' principal points (and distortion) are used. Focal hypotheses outside [0.1, 10] x
    max_image_dim are discarded; max_image_dim defaults to the largest known image side (no bounds if unknown).
    """
    return _estimate("shared_focal", kpts0, kpts1, depth0, depth1, camera0, camera1, options, method, image_size0,
                     image_size1, max_image_dim)


def estimate_two_focal_relative_pose(kpts0, kpts1, depth0, depth1, camera0, camera1, options=None, *,
                                     method="hybrid", image_size0=None, image_size1=None, max_image_dim=None):
    """As estimate_shared_focal_relative_pose, with a separate unknown focal length per view (result.f0, f1)."""
    return _estimate("two_focal", kpts0, kpts1, depth0, depth1, camera0, camera1, options, method, image_size0,
                     image_size1, max_image_dim)


def read_depth(path):
    """Reads a depth map (.npy, .pfm, COLMAP .bin) with the C++ reader: float32 array (H, W), values as stored.

    Raises FileNotFoundError for a missing file and ValueError ("depth file '<path>': ...") for a bad one.
    """
    path = os.fspath(path)
    if not isinstance(path, str):
        path = os.fsdecode(path)
    if not os.path.exists(path):
        raise FileNotFoundError(errno.ENOENT, "depth file not found", path)
    return _madsfm._read_depth(path)


def sample_depth(depth_map, kpts, image_size):
    """Samples `depth_map` (H', W') at `kpts` (N x 2, pixel centres at integers) of an image of
    image_size = (width, height) pixels, exactly as `madsfm pair` samples depth files: bilinear, NaN where a
    keypoint lies outside the image or touches an invalid (non-finite or <= 0) map pixel. The map must have the
    image's aspect ratio (within 1%). Returns float64 (N,).
    """
    array = _inputs.depth_map(depth_map, "depth_map")
    points = _inputs.keypoints(kpts, "kpts")
    size = _inputs.image_size(image_size, "image_size")
    if size is None:
        raise ValueError("image_size must be (width, height), got None")
    return _madsfm._sample_depth(array, points, size[0], size[1], "depth_map")


def _unpickle(cls, state):
    """Rebuilds a pickled HybridEstimatorOptions or RelativePoseResult (their __reduce__ names this function, so
    that every pickle protocol works: pybind11's own support aborts the interpreter with protocols 0 and 1)."""
    obj = cls.__new__(cls)
    obj.__setstate__(state)
    return obj
