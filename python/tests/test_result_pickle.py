"""madsfm.RelativePoseResult pickles (and copies) like the options do: a round trip gives back every field exactly."""

import copy
import math
import pickle
import struct

import numpy as np
import pytest

import madsfm
from conftest import DEPTH_PAIRS, ESTIMATORS, MODES, load_pair_numpy


def bits(x):
    return struct.pack("<d", x)


def assert_same_result(a, b):
    """Every attribute (to_dict lists them all) equal: floats bit for bit (NaN included), arrays element-wise."""
    da, db = a.to_dict(), b.to_dict()
    assert list(da) == list(db)
    for name, va in da.items():
        vb = db[name]
        if isinstance(va, np.ndarray):
            assert va.dtype == vb.dtype and va.shape == vb.shape, name
            assert va.tobytes() == vb.tobytes(), name  # bitwise: NaN == NaN, -0.0 != 0.0
        elif isinstance(va, float):
            assert bits(va) == bits(vb), (name, va, vb)
        else:
            assert type(va) is type(vb) and va == vb, (name, va, vb)
    assert repr(a) == repr(b)


def estimate(name, mode, **kwargs):
    p = load_pair_numpy(name)
    return ESTIMATORS[mode](p["kpts0"], p["kpts1"], p["depth0"], p["depth1"], p["K0"], p["K1"],
                            madsfm.HybridEstimatorOptions(seed=2), image_size0=p["image_size0"],
                            image_size1=p["image_size1"], **kwargs)


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("name", DEPTH_PAIRS)
def test_result_round_trips_through_pickle(name, mode):
    r = estimate(name, mode)
    assert r.success
    for protocol in range(pickle.HIGHEST_PROTOCOL + 1):
        back = pickle.loads(pickle.dumps(r, protocol=protocol))
        assert back is not r
        assert_same_result(back, r)
    assert_same_result(copy.deepcopy(r), r)
    assert_same_result(copy.copy(r), r)


def test_point_fallback_notes_and_a_failed_result_round_trip():
    r = estimate("0_scannet", "calibrated")
    assert r.notes == ["no depth: point method"]
    assert_same_result(pickle.loads(pickle.dumps(r)), r)
    # Five matches of pure noise: the estimate fails, its model attributes are NaN, and they stay NaN.
    rng = np.random.default_rng(0)
    kpts0, kpts1 = rng.uniform(0, 100, (5, 2)), rng.uniform(0, 100, (5, 2))
    K = np.array([[100.0, 0, 50], [0, 100.0, 50], [0, 0, 1]])
    failed = madsfm.estimate_relative_pose(kpts0, kpts1, np.ones(5), np.ones(5), K, K)
    if failed.success:
        pytest.skip("the noise happened to give an estimate")
    assert math.isnan(failed.scale)
    assert_same_result(pickle.loads(pickle.dumps(failed)), failed)


def test_the_comparison_notices_a_changed_field():
    # The check above can fail: a result from another seed differs in some field.
    a = estimate("1_eth3d", "calibrated")
    p = load_pair_numpy("1_eth3d")
    other = madsfm.estimate_relative_pose(p["kpts0"], p["kpts1"], p["depth0"], p["depth1"], p["K0"], p["K1"],
                                          madsfm.HybridEstimatorOptions(seed=3), image_size0=p["image_size0"],
                                          image_size1=p["image_size1"])
    with pytest.raises(AssertionError):
        assert_same_result(pickle.loads(pickle.dumps(other)), a)


def test_bad_state_is_refused_with_the_missing_key():
    r = estimate("1_eth3d", "calibrated")
    state = r.__getstate__()
    del state["scale"]
    clone = madsfm.RelativePoseResult.__new__(madsfm.RelativePoseResult)
    with pytest.raises(ValueError, match="'scale'"):
        clone.__setstate__(state)
    state = r.__getstate__()
    state["version"] = 99
    with pytest.raises(ValueError, match="version 99"):
        clone.__setstate__(state)
