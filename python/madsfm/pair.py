"""python3 -m madsfm.pair DIR: the example-pair demo, printing what `madsfm pair --pair_path DIR` prints.

Reads a pair directory (docs/formats.md) with the C++ reader, then estimates through the public Python API
(depth maps sampled by estimate_*, cameras as the 3 x 3 K of info.json), so that its JSON equals the C++ command's
for the same options and seed (runtime_ms aside).
"""

import argparse
import json
import math
import sys

from . import _madsfm
from ._api import estimate_relative_pose, estimate_shared_focal_relative_pose, estimate_two_focal_relative_pose

ESTIMATORS = {
    "calibrated": estimate_relative_pose,
    "shared_focal": estimate_shared_focal_relative_pose,
    "two_focal": estimate_two_focal_relative_pose,
}
# The estimator options `madsfm pair` exposes as flags (its EstimatorFlags), with the C++ defaults.
FLAG_OPTIONS = ("reproj_threshold", "epipolar_threshold", "sampson_weight", "min_iterations", "max_iterations",
                "num_lo_steps", "confidence", "final_reprojection_weight")


def read_pair(path):
    """A pair directory as a dict (K0, K1, T_0to1 or None, kpts0, kpts1, depth0/depth1 maps or None, image_size0,
    image_size1, warnings), read by the C++ reader of `madsfm pair` (a named but missing depth file is a warning)."""
    return _madsfm._read_pair_directory(str(path), True)


def _errors(result, pair, camera_mode):
    """Errors against T_0to1 as `madsfm pair` reports them (failures count as 180 degrees and focal error 1)."""
    T = pair["T_0to1"]
    if T is None:
        return {}
    if not result.success:
        out = {"rot_err_deg": 180.0, "trans_err_deg": 180.0}
        if camera_mode != "calibrated":
            out["focal_err"] = 1.0
        return out
    out = {"rot_err_deg": _madsfm.rotation_error_deg(result.R, T[:3, :3]),
           "trans_err_deg": _madsfm.translation_error_deg(result.t, T[:3, 3])}
    K0, K1 = pair["K0"], pair["K1"]
    fgt0 = 0.5 * (K0[0, 0] + K0[1, 1])
    fgt1 = 0.5 * (K1[0, 0] + K1[1, 1])
    if camera_mode == "shared_focal":
        fgt = 0.5 * (fgt0 + fgt1)
        out["focal_err"] = abs(result.f0 - fgt) / fgt
    elif camera_mode == "two_focal":
        out["focal_err"] = max(abs(result.f0 - fgt0) / fgt0, abs(result.f1 - fgt1) / fgt1)
    return out


def result_json(path, method, result, pair):
    """The JSON object of `madsfm pair` (same keys; non-finite numbers as null, as the C++ JSON library writes
    them)."""
    j = {"pair": path, "method": method, "camera_mode": result.camera_mode,
         "status": "ok" if result.success else "failed", "num_matches": result.num_matches,
         "num_matches_with_depth": result.num_matches_with_depth}
    if result.success:
        j["R"] = [float(v) for v in result.R.reshape(-1)]
        j["t"] = [float(v) for v in result.t]
        j.update(scale=result.scale, shift0=result.shift0, shift1=result.shift1, f0=result.f0, f1=result.f1)
        j["inliers"] = {"reproj_0to1": result.num_inliers_reproj0, "reproj_1to0": result.num_inliers_reproj1,
                        "sampson": result.num_inliers_sampson}
        j.update(depth_observable=result.depth_observable, sigma_scale=result.sigma_scale,
                 sigma_shift0=result.sigma_shift0, sigma_shift1=result.sigma_shift1,
                 shifts_dropped=result.shifts_dropped, scale_reset=result.scale_reset,
                 low_parallax_weighting=result.low_parallax_weighting)
        if result.camera_mode != "calibrated":
            j.update(sigma_focal0=result.sigma_focal0, sigma_focal1=result.sigma_focal1)
    j["iterations"] = result.iterations
    j["runtime_ms"] = result.runtime_ms
    j.update(_errors(result, pair, result.camera_mode))
    notes = list(pair["warnings"]) + list(result.notes)
    if notes:
        j["notes"] = notes
    return _null_non_finite(j)


def _null_non_finite(value):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _null_non_finite(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_null_non_finite(v) for v in value]
    return value


def run_pair(path, camera_mode="calibrated", method="hybrid", options=None):
    """Estimates one pair directory like `madsfm pair`; returns (result, JSON dict). Raises on bad input."""
    options = options if options is not None else _madsfm.HybridEstimatorOptions()
    _madsfm.HybridEstimatorOptions.for_method(method, options)  # validates the name
    options.check()
    pair = read_pair(path)
    if len(pair["kpts0"]) < 5:
        raise ValueError(f"pair directory '{path}' has {len(pair['kpts0'])} matches (at least 5 needed)")
    result = ESTIMATORS[camera_mode](pair["kpts0"], pair["kpts1"], pair["depth0"], pair["depth1"], pair["K0"],
                                     pair["K1"], options, method=method, image_size0=pair["image_size0"],
                                     image_size1=pair["image_size1"])
    return result, result_json(str(path), method, result, pair)


def _parser():
    defaults = _madsfm.HybridEstimatorOptions()
    p = argparse.ArgumentParser(
        prog="python3 -m madsfm.pair",
        description="Estimates the relative pose, depth scale/shifts (and focal lengths) of one pair directory "
                    "(docs/formats.md) and prints the result as JSON, with errors against T_0to1 if present; "
                    "the Python twin of `madsfm pair`.")
    p.add_argument("pair_dir", nargs="?", metavar="DIR", help="Pair directory holding info.json.")
    p.add_argument("--pair_path", help="Same as DIR (the C++ command's spelling).")
    p.add_argument("--camera_mode", default="calibrated", choices=sorted(ESTIMATORS))
    p.add_argument("--method", default="hybrid", help=" | ".join(_madsfm.METHODS) + " (default: hybrid)")
    p.add_argument("--seed", type=int, default=0, help="Random seed (default: 0).")
    for name in FLAG_OPTIONS:
        value = getattr(defaults, name)
        p.add_argument(f"--{name}", type=type(value), default=value, help=f"(default: {value})")
    return p


def main(argv=None):
    parser = _parser()
    args = parser.parse_args(argv)
    if (args.pair_dir is None) == (args.pair_path is None):
        parser.error("give the pair directory once, as DIR or --pair_path DIR")
    path = args.pair_dir if args.pair_dir is not None else args.pair_path
    try:
        options = _madsfm.HybridEstimatorOptions(**{name: getattr(args, name) for name in FLAG_OPTIONS})
        options.seed = args.seed % 2**64  # the C++ command casts its int seed to uint64 the same way
        result, j = run_pair(path, args.camera_mode, args.method, options)
    except (ValueError, TypeError, RuntimeError, OSError) as e:
        print(f"madsfm.pair: error: {e}", file=sys.stderr)
        return 1
    for note in j.get("notes", []):
        print(f"madsfm.pair: note: {note}", file=sys.stderr)
    print(json.dumps(j, indent=2, sort_keys=True, ensure_ascii=False))
    return 0 if result.success else 1


if __name__ == "__main__":
    sys.exit(main())
