"""No reference or memory leaks over 10,000 calls (successful and failing), on small synthetic inputs."""

import gc
import os
import sys
import tracemalloc

import numpy as np
import pytest

import madsfm
from conftest import fast_options, small_scene

CALLS = 10_000


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


@pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="needs /proc")
def test_ten_thousand_calls_do_not_leak():
    # 200 matches: leaking even one per-call copy of a depth vector (1.6 KB) would add 16 MB over the loop.
    s = small_scene(n=200, seed=11)
    camera = {"model": "PINHOLE", "width": 640, "height": 480, "params": [500.0, 500.0, 320.5, 240.5]}
    options = fast_options()
    bad_options = madsfm.HybridEstimatorOptions(confidence=2.0)  # rejected inside the C++ call
    depth_map = np.full((48, 64), 3.0, dtype=np.float32)
    inputs = [s["kpts0"], s["kpts1"], s["depth0"], s["depth1"], s["K"], camera, options, bad_options, depth_map]
    types = [madsfm.RelativePoseResult, madsfm.HybridEstimatorOptions, np.ndarray, ValueError]

    def one_round():
        r = madsfm.estimate_relative_pose(s["kpts0"], s["kpts1"], s["depth0"], s["depth1"], s["K"], camera, options)
        assert r.success
        # Every getter builds new objects (arrays, lists, dicts): they must be released too.
        r.R, r.t, r.inliers_sampson, r.inliers_reproj0, r.notes, r.to_dict(), repr(r), repr(options)
        with pytest.raises(ValueError):
            madsfm.estimate_relative_pose(s["kpts0"], s["kpts1"], s["depth0"], s["depth1"], s["K"], s["K"],
                                          bad_options)
        madsfm.sample_depth(depth_map, s["kpts0"] / 10.0, (64, 48))

    for _ in range(200):  # warm-up: caches, allocator pools, lazily created type objects
        one_round()
    gc.collect()
    refs_before = [sys.getrefcount(x) for x in inputs + types]
    objects_before = len(gc.get_objects())
    rss_before = rss_bytes()
    tracemalloc.start()
    traced_before = tracemalloc.get_traced_memory()[0]
    for _ in range(CALLS):
        one_round()
    gc.collect()
    traced_growth = tracemalloc.get_traced_memory()[0] - traced_before
    tracemalloc.stop()
    rss_growth = rss_bytes() - rss_before
    assert [sys.getrefcount(x) for x in inputs + types] == refs_before
    assert len(gc.get_objects()) - objects_before < 100
    assert traced_growth < 1_000_000, f"Python-level memory grew by {traced_growth} bytes"
    assert rss_growth < 5_000_000, f"RSS grew by {rss_growth} bytes over {CALLS} calls"
