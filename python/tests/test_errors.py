"""Bad input raises TypeError / ValueError whose message names the offending argument."""

import re

import numpy as np
import pytest

import madsfm
from conftest import fast_options, small_scene

SCENE = small_scene(n=12)
N = 12
K = SCENE["K"]
PINHOLE = {"model": "PINHOLE", "width": 640, "height": 480, "params": [500.0, 500.0, 320.5, 240.5]}


def call(**overrides):
    args = dict(kpts0=SCENE["kpts0"], kpts1=SCENE["kpts1"], depth0=SCENE["depth0"], depth1=SCENE["depth1"],
                camera0=K, camera1=K, options=fast_options())
    args.update(overrides)
    return madsfm.estimate_relative_pose(**args)


def with_row(array, row, value):
    array = np.array(array, dtype=float)
    array[row] = value
    return array


def test_valid_call_succeeds():
    # The baseline every case below breaks in one argument.
    assert call().success


@pytest.mark.parametrize("overrides, error, message", [
    # keypoints: shape, dtype, values, lengths
    (dict(kpts0=np.zeros((5, 3))), ValueError, "kpts0 must be an N x 2 array of pixel coordinates, got shape (5, 3)"),
    (dict(kpts1=np.zeros(24)), ValueError, "kpts1 must be an N x 2 array of pixel coordinates, got shape (24,)"),
    (dict(kpts0=SCENE["kpts0"].astype(complex)), TypeError,
     "kpts0 must be a real-valued numeric array, got dtype complex128"),
    (dict(kpts0=SCENE["kpts0"].astype(object)), TypeError,
     "kpts0 must be a real-valued numeric array, got dtype object"),
    (dict(kpts1="kpts.npy"), TypeError, "kpts1 must be a numeric array, got str"),
    (dict(kpts0=np.array([["1", "2"]])), TypeError, "kpts0 must be a real-valued numeric array, got dtype <U1"),
    (dict(kpts0=np.ones((N, 2), dtype=bool)), TypeError, "kpts0 must be a real-valued numeric array, got dtype bool"),
    (dict(kpts0=[[1.0, 2.0], [3.0]]), ValueError, "kpts0 could not be converted to a numeric array"),
    (dict(kpts0=with_row(SCENE["kpts0"], 2, np.nan)), ValueError,
     "kpts0 has 1 rows with non-finite coordinates (first: row 2)"),
    (dict(kpts1=with_row(with_row(SCENE["kpts1"], 4, np.inf), 7, -np.inf)), ValueError,
     "kpts1 has 2 rows with non-finite coordinates (first: row 4)"),
    (dict(kpts1=SCENE["kpts1"][:10]), ValueError, "kpts1 has 10 rows but kpts0 has 12"),
    # depths: lengths, infinities, dtypes, shapes, maps without image size, aspect ratio
    (dict(depth0=np.ones(11)), ValueError, "depth0 has 11 values but there are 12 keypoints"),
    (dict(depth1=with_row(with_row(SCENE["depth1"], 1, np.inf), 3, -np.inf)), ValueError,
     "depth1 has 2 infinite values (first: index 1); use NaN for keypoints without depth"),
    (dict(depth0=np.ones(N, dtype=complex)), TypeError,
     "depth0 must be a real-valued numeric array, got dtype complex128"),
    (dict(depth1=["a"] * N), TypeError, "depth1 must be a real-valued numeric array, got dtype <U1"),
    (dict(depth0=np.ones((2, 3, 4))), ValueError,
     "depth0 must be a non-empty 2-D depth map (H, W), got shape (2, 3, 4)"),
    (dict(depth0=np.ones((2, 3, 4, 5))), ValueError,
     "depth0 must be per-keypoint depths (N,) or a depth map (H, W), got shape (2, 3, 4, 5)"),
    (dict(depth1=np.ones((N, 1))), ValueError, "depth1 has shape (12, 1): give per-keypoint depths as a 1-D array"),
    (dict(depth0=np.ones((48, 64))), ValueError,
     "depth0 is a depth map, so the image size is needed to sample it: give camera0 as a dict with width and "
     "height, or image_size0=(width, height)"),
    (dict(depth1=np.ones((64, 48)), camera1=PINHOLE), ValueError,
     "depth1: the depth map is 48x64 (aspect ratio 0.75) but the image is 640x480 (aspect ratio 1.333); they differ "
     "by more than 1%"),
    # cameras: kinds, matrices, dicts
    (dict(camera0="PINHOLE"), TypeError, "camera0 must be a camera dict (model, width, height, params) or a 3 x 3 "
                                         "matrix K, got str"),
    (dict(camera1=np.eye(3)[:, :2]), ValueError, "camera1 must be a camera dict (model, width, height, params) or a "
                                                 "3 x 3 matrix K, got shape (3, 2)"),
    (dict(camera0=with_row(K, 0, [500.0, 0.0, np.nan])), ValueError, "camera0 has non-finite entries"),
    (dict(camera1=with_row(K, 2, [0.0, 0.0, 2.0])), ValueError, "camera1 must look like [[fx, 0, cx], [0, fy, cy], "
                                                               "[0, 0, 1]]"),
    (dict(camera0=with_row(K, 0, [500.0, 3.0, 320.0])), ValueError,
     "camera0 has skew K[0, 1] = 3.0, which madsfm does not model"),
    (dict(camera1=with_row(K, 1, [0.0, -500.0, 240.0])), ValueError,
     "camera1: focal lengths must be positive, got fx = 500.0, fy = -500.0"),
    (dict(camera0={"model": "PINHOLE", "width": 640, "height": 480}), ValueError,
     "camera0 is missing 'params' (a camera dict needs model, width, height and params)"),
    (dict(camera1=dict(PINHOLE, model="PINHOLISH")), ValueError,
     "camera1: unsupported camera model 'PINHOLISH' (supported: SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL"),
    (dict(camera0=dict(PINHOLE, model="FOV", params=[500.0, 500.0, 320.0, 240.0, 0.1])), ValueError,
     "camera0: unsupported camera model 'FOV'"),
    (dict(camera0=dict(PINHOLE, model=99)), ValueError, "camera0: unsupported camera model id 99"),
    (dict(camera0=dict(PINHOLE, model=1.0)), TypeError,
     "camera0: 'model' must be a COLMAP model name or id, got float"),
    (dict(camera1=dict(PINHOLE, params=[500.0, 320.0, 240.0])), ValueError,
     "camera1: a PINHOLE camera has 4 params, got shape (3,)"),
    (dict(camera0=dict(PINHOLE, params=[500.0, np.inf, 320.0, 240.0])), ValueError,
     "camera0['params'] has non-finite values"),
    (dict(camera0=dict(PINHOLE, params=["a", "b", "c", "d"])), TypeError,
     "camera0['params'] must be a real-valued numeric array, got dtype <U1"),
    (dict(camera1=dict(PINHOLE, width=0)), ValueError, "camera1['width'] must be a positive integer, got 0"),
    (dict(camera0=dict(PINHOLE, height=480.5)), TypeError,
     "camera0['height'] must be a positive integer, got float (480.5)"),
    (dict(camera0=PINHOLE, image_size0=(320, 240)), ValueError,
     "image_size0 = (320, 240) differs from camera0's width and height (640, 480)"),
    (dict(image_size1=(640, 480, 3)), ValueError, "image_size1 must be (width, height), got (640, 480, 3)"),
    (dict(image_size0=(640, -1)), ValueError, "image_size0[1] (height) must be a positive integer, got -1"),
    # options and method
    (dict(options="fast"), TypeError,
     "options must be a madsfm.HybridEstimatorOptions or a dict of its fields, got str"),
    (dict(options={"min_iterations": 10, "max_iteration": 20}), TypeError,
     "HybridEstimatorOptions has no option 'max_iteration' (options: reproj_threshold, "),
    (dict(options={"confidence": 2.0}), ValueError, "invalid estimator option: confidence must be in (0, 1)"),
    (dict(options={"min_iterations": 50, "max_iterations": 10}), ValueError,
     "invalid estimator option: max_iterations must be >= min_iterations"),
    (dict(options={"min_iterations": 2.5}), TypeError,
     "HybridEstimatorOptions.min_iterations must be an int, got float (2.5)"),
    (dict(method="magic"), ValueError,
     "unknown method 'magic' (expected hybrid, points, depth_only, no_shift or sampson_score)"),
    (dict(method=None), TypeError, "method must be a str (hybrid, points, depth_only, no_shift, sampson_score), got "
                                   "NoneType"),
])
def test_bad_argument(overrides, error, message):
    with pytest.raises(error, match=re.escape(message)):
        call(**overrides)


def test_focal_modes_check_the_same_arguments():
    for estimate in (madsfm.estimate_shared_focal_relative_pose, madsfm.estimate_two_focal_relative_pose):
        with pytest.raises(ValueError, match=re.escape("kpts1 has 10 rows but kpts0 has 12")):
            estimate(SCENE["kpts0"], SCENE["kpts1"][:10], None, None, K, K)
        with pytest.raises(ValueError, match=re.escape("camera0 is missing 'width'")):
            estimate(SCENE["kpts0"], SCENE["kpts1"], None, None, {"model": "PINHOLE"}, K)


def test_nan_and_non_positive_depths_mean_no_depth():
    depth0 = SCENE["depth0"].copy()
    depth0[[0, 3]] = np.nan
    depth0[5] = -1.0
    depth0[6] = 0.0
    result = call(depth0=depth0)
    assert result.success and result.num_matches_with_depth == N - 4 and result.notes == []


def test_too_few_depths_fall_back_to_points_with_a_note():
    depth1 = np.full(N, np.nan)
    depth1[:3] = 1.0
    result = call(depth1=depth1)
    assert result.num_matches_with_depth == 3
    assert result.notes == ["fewer than 4 matches with valid depth in both views: point method"]
    assert call(depth0=None).notes == ["no depth: point method"]


def test_too_few_matches_is_a_failed_result_not_an_exception():
    result = call(kpts0=SCENE["kpts0"][:2], kpts1=SCENE["kpts1"][:2], depth0=SCENE["depth0"][:2],
                  depth1=SCENE["depth1"][:2])
    assert not result.success
    assert np.isnan(result.R).all() and np.isnan(result.t).all() and np.isnan(result.scale)
    assert result.f0 == 500.0  # calibrated: the cameras' focal, known regardless
    assert result.inliers_sampson.shape == (2,) and not result.inliers_sampson.any()
    empty = call(kpts0=np.zeros((0, 2)), kpts1=np.zeros((0, 2)), depth0=np.zeros(0), depth1=np.zeros(0))
    assert not empty.success and empty.num_matches == 0


def test_read_depth_errors(tmp_path):
    missing = tmp_path / "missing.npy"
    with pytest.raises(FileNotFoundError, match=re.escape(str(missing))):
        madsfm.read_depth(missing)
    bad = tmp_path / "bad.npy"
    bad.write_bytes(b"not an npy file")
    with pytest.raises(ValueError, match=re.escape(f"depth file '{bad}': ")):
        madsfm.read_depth(bad)
    text = tmp_path / "depth.txt"
    text.write_text("1 2 3")
    with pytest.raises(ValueError, match=re.escape(f"depth file '{text}': ")):
        madsfm.read_depth(str(text))
    ints = tmp_path / "ints.npy"
    np.save(ints, np.ones((4, 5), dtype=np.int32))
    with pytest.raises(ValueError, match=re.escape(f"depth file '{ints}': ")):
        madsfm.read_depth(ints)


@pytest.mark.parametrize("args, error, message", [
    ((np.ones((48, 64)), np.zeros((3, 2)), None), ValueError, "image_size must be (width, height), got None"),
    ((np.ones((48, 64)), np.zeros((3, 2)), (64, 48, 1)), ValueError, "image_size must be (width, height)"),
    ((np.ones((48, 64)), np.array([[1.0, np.nan]]), (64, 48)), ValueError,
     "kpts has 1 rows with non-finite coordinates (first: row 0)"),
    ((np.ones((48, 64)), np.zeros((3, 3)), (64, 48)), ValueError, "kpts must be an N x 2 array"),
    ((np.ones(64), np.zeros((3, 2)), (64, 48)), ValueError, "depth_map must be a non-empty 2-D depth map (H, W), got "
                                                             "shape (64,)"),
    ((np.ones((48, 64), dtype=complex), np.zeros((3, 2)), (64, 48)), TypeError,
     "depth_map must be a real-valued numeric array, got dtype complex128"),
    ((np.ones((48, 64)), np.zeros((3, 2)), (48, 64)), ValueError,
     "depth_map: the depth map is 64x48 (aspect ratio 1.333) but the image is 48x64"),
])
def test_sample_depth_errors(args, error, message):
    with pytest.raises(error, match=re.escape(message)):
        madsfm.sample_depth(*args)


def test_pose_error_shapes():
    with pytest.raises(ValueError, match="R_est must be 3 x 3"):
        madsfm.rotation_error_deg(np.eye(2), np.eye(3))
    with pytest.raises(ValueError, match="t_gt must have 3 elements"):
        madsfm.translation_error_deg(np.ones(3), np.ones(4))
