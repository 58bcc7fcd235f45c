#!/usr/bin/env python3
"""Per pair, one method against another (issue 12's "on low-parallax pairs the hybrid pose is never worse than the
point-only pose"): the median over seeds of each pair's pose error max(rot, trans) (failures count as 180 deg) from
`madsfm bench`'s per_pair.csv, and the pairs where method A is better / worse than method B by more than MARGIN deg.
Also the same per run (seed by seed), since one seed of a pair can be worse while the median is not.
Usage: pair_ordering.py PER_PAIR_CSV [A=hybrid] [B=points] [MARGIN=1]"""
import csv
import statistics
import sys
from collections import defaultdict


def pose_error(row):
    if row["status"] != "ok":
        return 180.0
    try:
        t = float(row["trans_err_deg"])
        return max(float(row["rot_err_deg"]), min(t, 180.0 - t))
    except ValueError:
        return 180.0


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    path = sys.argv[1]
    a = sys.argv[2] if len(sys.argv) > 2 else "hybrid"
    b = sys.argv[3] if len(sys.argv) > 3 else "points"
    margin = float(sys.argv[4]) if len(sys.argv) > 4 else 1.0
    err = defaultdict(dict)  # (pair) -> {(method, seed): error}
    with open(path) as f:
        for r in csv.DictReader(f):
            err[r["pair"]][(r["method"], r["seed"])] = pose_error(r)
    better = worse = runs_better = runs_worse = runs = 0
    worse_pairs = []
    for pair, e in sorted(err.items()):
        seeds = sorted({s for (m, s) in e if m == a} & {s for (m, s) in e if m == b})
        if not seeds:
            continue
        ea = statistics.median(e[(a, s)] for s in seeds)
        eb = statistics.median(e[(b, s)] for s in seeds)
        if ea < eb - margin:
            better += 1
        elif ea > eb + margin:
            worse += 1
            worse_pairs.append(f"{pair.rsplit('_', 1)[-1]} {ea:.1f}/{eb:.1f}")
        for s in seeds:
            runs += 1
            runs_better += e[(a, s)] < e[(b, s)] - margin
            runs_worse += e[(a, s)] > e[(b, s)] + margin
    print(f"{path}: {a} vs {b}, margin {margin} deg: pairs (median over seeds) better {better} / worse {worse}; "
          f"runs better {runs_better} / worse {runs_worse} of {runs}")
    if worse_pairs:
        print("  worse pairs (A/B deg): " + ", ".join(worse_pairs))


if __name__ == "__main__":
    main()
