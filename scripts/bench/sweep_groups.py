#!/usr/bin/env python3
"""Compares two groups of `madsfm bench` sweeps (scripts/bench/estimator_sweep.sh), each group the same estimator
run with different seed offsets (BENCH_ARGS="--seed 0", "--seed 10", ...): per set and method, the mean AUC@10 of
each group, the difference of the means and each group's spread (population standard deviation over its sweeps), then
the sums. A change to the estimator alters its random stream as a change of seed does, so a difference only counts
where it is larger than the spread of the sweeps within a group (docs/benchmarks.md section 11, update of
2026-12-06: with 3 seeds per pair, one low-parallax set moved by 7.6 AUC@10 between seed offsets).
Usage: sweep_groups.py A1,A2[,...] B1,B2[,...]"""
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sweep_table import load  # noqa: E402  (set, method) -> summary of one sweep


def auc10(d):
    return {key: 100 * v["auc@10"] for key, v in load(d).items()}


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    groups = [[auc10(d) for d in arg.split(",")] for arg in sys.argv[1:]]
    keys = sorted(set.intersection(*(set(s) for g in groups for s in g)))
    print("| set | method | A mean (sd) | B mean (sd) | B - A |")
    print("|---|---|---|---|---|")
    sums = [0.0, 0.0]
    for key in keys:
        cells = []
        means = []
        for k, g in enumerate(groups):
            v = [s[key] for s in g]
            means.append(statistics.mean(v))
            sums[k] += means[-1]
            cells.append(f"{means[-1]:.2f} ({statistics.pstdev(v):.2f})")
        print(f"| {key[0]} | {key[1]} | {cells[0]} | {cells[1]} | {means[1] - means[0]:+.2f} |")
    print(f"| sum | | {sums[0]:.2f} | {sums[1]:.2f} | {sums[1] - sums[0]:+.2f} |")


if __name__ == "__main__":
    main()
