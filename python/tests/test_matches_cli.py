"""The Python API and `python3 -m madsfm.pair` give exactly what the C++ `madsfm pair` command gives, same seed."""

import json
import subprocess
import sys

import numpy as np
import pytest

import madsfm
from conftest import DEPTH_PAIRS, ESTIMATORS, EXAMPLE_PAIRS, MODES, load_pair_numpy, run_cli_pair

SEED = 3


def estimate_like_cli(pair, mode, **kwargs):
    options = madsfm.HybridEstimatorOptions(seed=SEED)
    return ESTIMATORS[mode](pair["kpts0"], pair["kpts1"], pair["depth0"], pair["depth1"], pair["K0"], pair["K1"],
                            options, image_size0=pair["image_size0"], image_size1=pair["image_size1"], **kwargs)


def assert_equals_cli_json(result, j):
    """Bit-identical: every number of the C++ JSON equals the Python result's."""
    assert result.success == (j["status"] == "ok")
    assert result.num_matches == j["num_matches"]
    assert result.num_matches_with_depth == j["num_matches_with_depth"]
    assert result.iterations == j["iterations"]
    assert result.success, "the example pairs are expected to succeed"
    np.testing.assert_array_equal(result.R.reshape(-1), j["R"])
    np.testing.assert_array_equal(result.t, j["t"])
    for name in ("scale", "shift0", "shift1", "f0", "f1"):
        assert getattr(result, name) == j[name], name
    if result.camera_mode != "calibrated":
        assert (result.sigma_focal0, result.sigma_focal1) == (j["sigma_focal0"], j["sigma_focal1"])
    assert (result.shifts_dropped, result.scale_reset) == (j["shifts_dropped"], j["scale_reset"])
    assert result.low_parallax_weighting == j["low_parallax_weighting"]
    assert (result.num_inliers_reproj0, result.num_inliers_reproj1, result.num_inliers_sampson) == (
        j["inliers"]["reproj_0to1"], j["inliers"]["reproj_1to0"], j["inliers"]["sampson"])
    # The masks agree with the counts.
    assert result.inliers_reproj0.sum() == result.num_inliers_reproj0
    assert result.inliers_reproj1.sum() == result.num_inliers_reproj1
    assert result.inliers_sampson.sum() == result.num_inliers_sampson


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("name", DEPTH_PAIRS)
def test_api_equals_cli_on_example_pairs(cli, name, mode):
    code, j, _ = run_cli_pair(cli, EXAMPLE_PAIRS / name, "--camera_mode", mode, "--seed", str(SEED))
    assert code == 0
    result = estimate_like_cli(load_pair_numpy(name), mode)
    assert result.camera_mode == mode and result.method == "hybrid" and result.notes == []
    assert_equals_cli_json(result, j)


@pytest.mark.parametrize("method", ["points", "no_shift", "depth_only", "sampson_score"])
def test_api_methods_equal_cli(cli, method):
    code, j, _ = run_cli_pair(cli, EXAMPLE_PAIRS / "1_eth3d", "--seed", str(SEED), "--method", method)
    assert code == 0
    assert_equals_cli_json(estimate_like_cli(load_pair_numpy("1_eth3d"), "calibrated", method=method), j)


def test_api_point_fallback_equals_cli_without_depth(cli):
    # 0_scannet names depth files it does not ship: the command falls back to the point method, so must the API.
    code, j, _ = run_cli_pair(cli, EXAMPLE_PAIRS / "0_scannet", "--seed", str(SEED))
    assert code == 0
    pair = load_pair_numpy("0_scannet")
    assert pair["depth0"] is None and pair["depth1"] is None
    result = estimate_like_cli(pair, "calibrated")
    assert result.notes == ["no depth: point method"] and j["notes"][-1] == "no depth: point method"
    assert_equals_cli_json(result, j)


def test_colmap_dict_cameras_equal_matrices():
    # A PINHOLE dict holds COLMAP's principal point (+0.5): converted, it is the same camera as K.
    pair = load_pair_numpy("1_eth3d")
    dicts = []
    for i in (0, 1):
        K = pair[f"K{i}"]
        assert (K[0, 2] + 0.5) - 0.5 == K[0, 2] and (K[1, 2] + 0.5) - 0.5 == K[1, 2]  # exact round trip
        w, h = pair[f"image_size{i}"]
        dicts.append({"model": "PINHOLE", "width": w, "height": h,
                      "params": [K[0, 0], K[1, 1], K[0, 2] + 0.5, K[1, 2] + 0.5]})
    for mode in MODES:
        a = estimate_like_cli(pair, mode)
        b = ESTIMATORS[mode](pair["kpts0"], pair["kpts1"], pair["depth0"], pair["depth1"], dicts[0], dicts[1],
                             {"seed": SEED})
        np.testing.assert_array_equal(a.R, b.R)
        np.testing.assert_array_equal(a.t, b.t)
        assert (a.scale, a.shift0, a.shift1, a.f0, a.f1) == (b.scale, b.shift0, b.shift1, b.f0, b.f1)


def test_depth_maps_sampled_like_sample_depth():
    pair = load_pair_numpy("2_2d3ds")
    d0 = madsfm.sample_depth(pair["depth0"], pair["kpts0"], pair["image_size0"])
    d1 = madsfm.sample_depth(pair["depth1"], pair["kpts1"], pair["image_size1"])
    assert np.isfinite(d0).sum() > 0.9 * len(d0)
    a = estimate_like_cli(pair, "two_focal")
    b = madsfm.estimate_two_focal_relative_pose(pair["kpts0"], pair["kpts1"], d0, d1, pair["K0"], pair["K1"],
                                                {"seed": SEED}, image_size0=pair["image_size0"],
                                                image_size1=pair["image_size1"])
    np.testing.assert_array_equal(a.R, b.R)
    assert (a.scale, a.f0, a.f1, a.num_inliers_sampson) == (b.scale, b.f0, b.f1, b.num_inliers_sampson)


def run_python_pair(*args):
    proc = subprocess.run([sys.executable, "-m", "madsfm.pair", *args], capture_output=True, text=True, timeout=300)
    return proc.returncode, proc.stdout, proc.stderr


def without_runtime(j):
    j = dict(j)
    assert isinstance(j.pop("runtime_ms"), float)
    return j


@pytest.mark.parametrize("name, args", [
    ("1_eth3d", ["--camera_mode", "calibrated"]),
    ("1_eth3d", ["--camera_mode", "shared_focal"]),
    ("1_eth3d", ["--camera_mode", "two_focal"]),
    ("2_2d3ds", ["--camera_mode", "two_focal", "--method", "no_shift", "--seed", "5", "--reproj_threshold", "16",
                 "--epipolar_threshold", "1", "--min_iterations", "200", "--final_reprojection_weight", "1"]),
    ("0_scannet", []),
])
def test_python_pair_prints_what_cli_prints(cli, name, args):
    pair_dir = str(EXAMPLE_PAIRS / name)
    code, out, err = run_python_pair(pair_dir, *args)
    cli_proc = subprocess.run([cli, "pair", "--pair_path", pair_dir, *args], capture_output=True, text=True,
                              timeout=300)
    assert code == cli_proc.returncode == 0, err
    # Same keys, same values (numbers compared after parsing: both sides print round-trip representations).
    assert without_runtime(json.loads(out)) == without_runtime(json.loads(cli_proc.stdout))
    assert err.replace("madsfm.pair:", "madsfm pair:") == cli_proc.stderr
    # Same layout: two-space indentation, sorted keys (the numbers themselves were compared as numbers above).
    assert [layout_of(line) for line in out.splitlines()] == [layout_of(line) for line in cli_proc.stdout.splitlines()]


def test_python_pair_prints_what_cli_prints_when_the_shifts_are_dropped(cli, tmp_path):
    """A low-parallax pair whose shifts the priors do not determine: both print the scale-only result and its note."""
    subprocess.run([cli, "synth", "--preset", "hard_low_parallax_calibrated", "--num_pairs", "1", "--seed", "5",
                    "--output_path", str(tmp_path)], check=True, capture_output=True, timeout=300)
    pair_dir = str(tmp_path / "hard_low_parallax_calibrated_0000")
    code, out, err = run_python_pair(pair_dir, "--camera_mode", "calibrated")
    cli_proc = subprocess.run([cli, "pair", "--pair_path", pair_dir, "--camera_mode", "calibrated"],
                              capture_output=True, text=True, timeout=300)
    assert code == cli_proc.returncode == 0, err
    j = json.loads(out)
    assert j["shifts_dropped"] is True and j["scale_reset"] is False
    assert (j["shift0"], j["shift1"]) == (0.0, 0.0)
    assert any("estimated again without shifts" in note for note in j["notes"]), j["notes"]
    assert without_runtime(j) == without_runtime(json.loads(cli_proc.stdout))


def layout_of(line):
    """A JSON line without its value if it is a number: the indentation and key, or "<number>" for an array element."""
    key, sep, value = line.partition(":")
    text = value if sep else key
    try:
        float(text.strip().rstrip(","))
        return (key if sep else key[:len(key) - len(key.lstrip())]) + "<number>"
    except ValueError:
        return line


def test_layout_of_ignores_digits_only():
    assert layout_of("    -0.007081597240052685,") == layout_of("    -0.0070815972400526846,") == "    <number>"
    assert layout_of('  "scale": 1.5,') == layout_of('  "scale": 1.50,') == '  "scale"<number>'
    assert layout_of('  "scale": 1.5,') != layout_of('  "shift": 1.5,')
    assert layout_of('  "R": [') != layout_of('  "t": [')
    assert layout_of("    1.0,") != layout_of("      1.0,")


def test_python_pair_accepts_pair_path_flag(cli):
    pair_dir = str(EXAMPLE_PAIRS / "1_eth3d")
    a = run_python_pair("--pair_path", pair_dir)
    b = run_python_pair(pair_dir)
    assert a[0] == b[0] == 0
    assert without_runtime(json.loads(a[1])) == without_runtime(json.loads(b[1]))


@pytest.mark.parametrize("args, message", [
    (["/nonexistent/pair"], "pair directory '/nonexistent/pair': does not exist"),
    ([str(EXAMPLE_PAIRS / "1_eth3d"), "--method", "magic"], "unknown method 'magic'"),
    ([str(EXAMPLE_PAIRS / "1_eth3d"), "--confidence", "2"], "confidence must be in (0, 1)"),
])
def test_python_pair_errors_like_cli(cli, args, message):
    code, out, err = run_python_pair(*args)
    assert code == 1 and out == ""
    assert err.startswith("madsfm.pair: error: ") and message in err
    cli_args = ["--pair_path", args[0], *args[1:]]
    cli_proc = subprocess.run([cli, "pair", *cli_args], capture_output=True, text=True, timeout=300)
    assert cli_proc.returncode == 1 and message in cli_proc.stderr


def test_python_pair_needs_one_directory():
    code, _, err = run_python_pair()
    assert code == 2 and "give the pair directory once" in err
