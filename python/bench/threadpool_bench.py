"""Throughput of madsfm.estimate_relative_pose from a Python thread pool (the GIL is released while estimating).

Estimates the example pair 1_eth3d (calibrated, depth maps sampled per call) `--calls` times with 1, 2, ...
`--max_threads` worker threads, `--repetitions` times each; prints the median pairs/s per thread count and the
ratio to one thread, measured in the same run. Usage, from the repository root:

  PYTHONPATH=build/python /usr/bin/python3 python/bench/threadpool_bench.py [--calls 200] [--repetitions 5]
"""
import argparse
import concurrent.futures
import json
import os
import statistics
import time

import numpy as np

import madsfm


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--pair", default="tests/data/example_pairs/1_eth3d")
    parser.add_argument("--calls", type=int, default=200)
    parser.add_argument("--repetitions", type=int, default=5)
    parser.add_argument("--max_threads", type=int, default=os.cpu_count() or 1)
    args = parser.parse_args()

    d = args.pair
    info = json.load(open(f"{d}/info.json"))
    kpts0, kpts1 = np.load(f"{d}/lightglue_matches_0.npy"), np.load(f"{d}/lightglue_matches_1.npy")
    depth0, depth1 = madsfm.read_depth(f"{d}/da-met_depth_0.npy"), madsfm.read_depth(f"{d}/da-met_depth_1.npy")
    K0, K1 = np.array(info["K0"]), np.array(info["K1"])
    size = (720, 480)

    def one(seed):
        options = madsfm.HybridEstimatorOptions(seed=seed)
        return madsfm.estimate_relative_pose(kpts0, kpts1, depth0, depth1, K0, K1, options,
                                             image_size0=size, image_size1=size).success

    one(0)  # warm-up
    rates = {}
    for threads in range(1, args.max_threads + 1):
        samples = []
        for _ in range(args.repetitions):
            start = time.perf_counter()
            with concurrent.futures.ThreadPoolExecutor(max_workers=threads) as pool:
                ok = sum(pool.map(one, range(args.calls)))
            samples.append(args.calls / (time.perf_counter() - start))
            assert ok == args.calls
        rates[threads] = statistics.median(samples)
    print(f"{'threads':>7} {'pairs/s (median of %d)' % args.repetitions:>24} {'vs 1 thread':>12}")
    for threads, rate in rates.items():
        print(f"{threads:>7} {rate:>24.1f} {rate / rates[1]:>11.2f}x")


if __name__ == "__main__":
    main()
