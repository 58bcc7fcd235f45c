"""Cameras: COLMAP dicts (distorted models undistorted), pycolmap-like objects, model ids, 3 x 3 matrices."""

import types

import numpy as np
import pytest

import madsfm
from conftest import small_scene

F, CX, CY = 500.0, 320.0, 240.0  # the scene's K, keypoint convention (centres at integers)


def distort(kpts, model, params):
    """COLMAP's distortion of undistorted pixels (keypoint convention), implemented independently here."""
    x = (kpts[:, 0] - CX) / F
    y = (kpts[:, 1] - CY) / F
    r2 = x * x + y * y
    if model == "SIMPLE_RADIAL":
        radial, dx, dy = params[0] * r2, 0.0, 0.0
    elif model == "RADIAL":
        radial, dx, dy = params[0] * r2 + params[1] * r2 * r2, 0.0, 0.0
    elif model == "OPENCV":
        k1, k2, p1, p2 = params
        radial = k1 * r2 + k2 * r2 * r2
        dx = 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
        dy = 2 * p2 * x * y + p1 * (r2 + 2 * y * y)
    xd = x + x * radial + dx
    yd = y + y * radial + dy
    return np.stack([F * xd + CX, F * yd + CY], axis=1)


def colmap_camera(model, distortion):
    # COLMAP's principal point is +0.5 from the keypoint convention's.
    pinhole = [F, CX + 0.5, CY + 0.5] if model != "OPENCV" else [F, F, CX + 0.5, CY + 0.5]
    return {"model": model, "width": 640, "height": 480, "params": pinhole + list(distortion)}


DISTORTIONS = [("SIMPLE_RADIAL", [-0.15]), ("RADIAL", [-0.1, 0.05]), ("OPENCV", [-0.1, 0.02, 0.002, -0.001])]


@pytest.mark.parametrize("model, distortion", DISTORTIONS)
def test_distorted_keypoints_are_undistorted(model, distortion):
    s = small_scene(n=60, seed=4, half_width=1.8)
    k0, k1 = distort(s["kpts0"], model, distortion), distort(s["kpts1"], model, distortion)
    assert np.abs(k0 - s["kpts0"]).max() > 5.0, "the distortion must matter"
    camera = colmap_camera(model, distortion)
    result = madsfm.estimate_relative_pose(k0, k1, s["depth0"], s["depth1"], camera, camera, {"seed": 1})
    assert result.success
    assert madsfm.rotation_error_deg(result.R, s["R"]) < 1e-4
    assert madsfm.translation_error_deg(result.t, s["t"]) < 1e-3
    assert result.scale == pytest.approx(2.0, rel=1e-5)
    # Ignoring the distortion (same pinhole part) is measurably worse: the undistortion did the work.
    pinhole = dict(camera, model="PINHOLE", params=[F, F, CX + 0.5, CY + 0.5])
    ignored = madsfm.estimate_relative_pose(k0, k1, s["depth0"], s["depth1"], pinhole, pinhole, {"seed": 1})
    assert madsfm.rotation_error_deg(ignored.R, s["R"]) > 0.5


@pytest.mark.parametrize("estimate", [madsfm.estimate_shared_focal_relative_pose,
                                      madsfm.estimate_two_focal_relative_pose])
def test_focal_modes_undistort_and_estimate_the_focal(estimate):
    model, distortion = DISTORTIONS[0]
    s = small_scene(n=60, seed=5, half_width=1.8)
    k0, k1 = distort(s["kpts0"], model, distortion), distort(s["kpts1"], model, distortion)
    camera = colmap_camera(model, distortion)
    result = estimate(k0, k1, s["depth0"], s["depth1"], camera, camera, {"seed": 2})
    assert result.success and result.camera_mode in ("shared_focal", "two_focal")
    assert result.f0 == pytest.approx(F, rel=1e-4) and result.f1 == pytest.approx(F, rel=1e-4)
    assert madsfm.rotation_error_deg(result.R, s["R"]) < 1e-3


def test_focal_modes_ignore_the_given_focal():
    s = small_scene(n=40, seed=6)
    K_wrong = np.array([[900.0, 0.0, CX], [0.0, 700.0, CY], [0.0, 0.0, 1.0]])
    a = madsfm.estimate_two_focal_relative_pose(s["kpts0"], s["kpts1"], s["depth0"], s["depth1"], s["K"], s["K"],
                                                {"seed": 3}, image_size0=(640, 480), image_size1=(640, 480))
    b = madsfm.estimate_two_focal_relative_pose(s["kpts0"], s["kpts1"], s["depth0"], s["depth1"], K_wrong, K_wrong,
                                                {"seed": 3}, image_size0=(640, 480), image_size1=(640, 480))
    np.testing.assert_array_equal(a.R, b.R)
    assert a.f0 == b.f0 == pytest.approx(F, rel=1e-6)


def test_zero_distortion_equals_pinhole():
    s = small_scene(n=40, seed=7)
    simple = {"model": "SIMPLE_PINHOLE", "width": 640, "height": 480, "params": [F, CX + 0.5, CY + 0.5]}
    radial = dict(simple, model="SIMPLE_RADIAL", params=[F, CX + 0.5, CY + 0.5, 0.0])
    a = madsfm.estimate_relative_pose(s["kpts0"], s["kpts1"], s["depth0"], s["depth1"], simple, simple, {"seed": 4})
    b = madsfm.estimate_relative_pose(s["kpts0"], s["kpts1"], s["depth0"], s["depth1"], radial, radial, {"seed": 4})
    np.testing.assert_allclose(a.R, b.R, atol=1e-9)
    assert a.scale == pytest.approx(b.scale, rel=1e-9)


def test_pycolmap_like_objects_and_model_ids():
    s = small_scene(n=40, seed=8)
    camera = {"model": "PINHOLE", "width": 640, "height": 480, "params": [F, F, CX + 0.5, CY + 0.5]}
    # pycolmap.Camera: attributes model (an enum with .name), width, height, params.
    obj = types.SimpleNamespace(model=types.SimpleNamespace(name="PINHOLE"), width=640, height=480,
                                params=np.array(camera["params"]))
    by_id = dict(camera, model=1, camera_id=7)  # COLMAP's id of PINHOLE; unrelated keys are ignored
    results = [madsfm.estimate_relative_pose(s["kpts0"], s["kpts1"], s["depth0"], s["depth1"], c, c, {"seed": 5})
               for c in (camera, obj, by_id, s["K"])]
    for r in results[1:]:
        np.testing.assert_array_equal(r.R, results[0].R)
        assert r.scale == results[0].scale
    assert madsfm.rotation_error_deg(results[0].R, s["R"]) < 1e-6


def test_dict_camera_gives_the_image_size_for_depth_maps():
    s = small_scene(n=40, seed=9)
    # A constant depth map at half resolution: every keypoint samples the same value.
    depth_map = np.full((240, 320), 4.0, dtype=np.float32)
    camera = {"model": "PINHOLE", "width": 640, "height": 480, "params": [F, F, CX + 0.5, CY + 0.5]}
    r = madsfm.estimate_relative_pose(s["kpts0"], s["kpts1"], depth_map, s["depth1"], camera, s["K"],
                                      {"min_iterations": 10, "max_iterations": 20})
    inside = ((s["kpts0"] >= -0.5) & (s["kpts0"] <= [639.5, 479.5])).all(axis=1)
    assert r.num_matches_with_depth == inside.sum() > 30
