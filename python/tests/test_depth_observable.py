"""RelativePoseResult says whether the depth corrections are determined (depth_observable, sigma_*), issue 12."""

import math

import madsfm
from conftest import DEPTH_PAIRS, ESTIMATORS, load_pair_numpy


def estimate(name):
    p = load_pair_numpy(name)
    return ESTIMATORS["calibrated"](p["kpts0"], p["kpts1"], p["depth0"], p["depth1"], p["K0"], p["K1"],
                                    madsfm.HybridEstimatorOptions(seed=0), image_size0=p["image_size0"],
                                    image_size1=p["image_size1"])


def test_example_pairs_have_observable_corrections_with_their_sigmas():
    for name in DEPTH_PAIRS:
        r = estimate(name)
        assert r.success, name
        sigmas = (r.sigma_scale, r.sigma_shift0, r.sigma_shift1)
        assert all(math.isfinite(s) and s >= 0 for s in sigmas), (name, sigmas)
        bound = madsfm.HybridEstimatorOptions().max_depth_sigma
        assert r.depth_observable == all(s <= bound for s in sigmas), (name, sigmas)
        d = r.to_dict()
        assert d["depth_observable"] is r.depth_observable
        assert d["sigma_scale"] == r.sigma_scale
        assert d["shifts_dropped"] is r.shifts_dropped is False and d["scale_reset"] is r.scale_reset is False


def test_point_fallback_is_not_observable():
    r = estimate("0_scannet")  # names depth files it does not ship: the point method
    assert r.success
    assert r.depth_observable is False
    assert math.isnan(r.sigma_scale) and math.isnan(r.sigma_shift0) and math.isnan(r.sigma_shift1)
