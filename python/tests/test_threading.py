"""Estimation releases the GIL: a thread pool over pairs gives the sequential results, and Python keeps running
while the C++ estimator works."""

import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

import madsfm
from conftest import DEPTH_PAIRS, ESTIMATORS, MODES, load_pair_numpy


def estimate(pair, mode, seed):
    return ESTIMATORS[mode](pair["kpts0"], pair["kpts1"], pair["depth0"], pair["depth1"], pair["K0"], pair["K1"],
                            madsfm.HybridEstimatorOptions(seed=seed), image_size0=pair["image_size0"],
                            image_size1=pair["image_size1"])


def test_thread_pool_equals_sequential():
    pairs = {name: load_pair_numpy(name) for name in DEPTH_PAIRS}  # shared, read-only, by every thread
    jobs = [(name, mode, seed) for name in DEPTH_PAIRS for mode in MODES for seed in (0, 1)]
    sequential = [estimate(pairs[n], m, s) for n, m, s in jobs]
    with ThreadPoolExecutor(max_workers=4) as pool:
        parallel = list(pool.map(lambda job: estimate(pairs[job[0]], job[1], job[2]), jobs))
    for job, a, b in zip(jobs, sequential, parallel):
        assert a.success and b.success, job
        np.testing.assert_array_equal(a.R, b.R)
        np.testing.assert_array_equal(a.t, b.t)
        assert (a.scale, a.shift0, a.shift1, a.f0, a.f1, a.iterations, a.score) == (
            b.scale, b.shift0, b.shift1, b.f0, b.f1, b.iterations, b.score), job
        np.testing.assert_array_equal(a.inliers_sampson, b.inliers_sampson)
        np.testing.assert_array_equal(a.inliers_reproj0, b.inliers_reproj0)
    # Different seeds and modes really are different jobs (the comparison above is not vacuous).
    assert len({(r.f0, r.scale) for r in sequential}) > len(jobs) // 2


def test_main_thread_runs_while_a_long_estimation_runs():
    pair = load_pair_numpy("2_2d3ds")
    d0 = madsfm.sample_depth(pair["depth0"], pair["kpts0"], pair["image_size0"])
    d1 = madsfm.sample_depth(pair["depth1"], pair["kpts1"], pair["image_size1"])
    iterations = 40000  # forced (min = max): a fraction of a second to a few seconds of C++
    options = madsfm.HybridEstimatorOptions(min_iterations=iterations, max_iterations=iterations,
                                            epipolar_check_ratio=0.0)
    out = {}

    def work():
        out["result"] = madsfm.estimate_relative_pose(pair["kpts0"], pair["kpts1"], d0, d1, pair["K0"], pair["K1"],
                                                      options)

    worker = threading.Thread(target=work)
    last = time.perf_counter()
    worker.start()
    max_gap, ticks = 0.0, 0
    # Count and record the longest pause of this loop: if the estimator held the GIL, the loop would stand still
    # for the whole estimation.
    while worker.is_alive():
        now = time.perf_counter()
        max_gap = max(max_gap, now - last)
        last = now
        ticks += 1
    worker.join()
    result = out["result"]
    assert result.success and result.iterations == iterations
    runtime = result.runtime_ms / 1000.0
    assert runtime > 0.2, "the estimation must be long enough to tell"
    assert ticks > 1000
    assert max_gap < 0.5 * runtime, f"main thread paused {max_gap:.3f} s during a {runtime:.3f} s estimation"
