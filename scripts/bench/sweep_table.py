#!/usr/bin/env python3
"""Side-by-side table of `madsfm bench` sweeps (scripts/bench/estimator_sweep.sh): per set and method, AUC@10, runs
> 5 deg, median focal error and runs with absurd shifts, one column group per sweep, and the sum of AUC@10.
Usage: sweep_table.py SWEEP_DIR [SWEEP_DIR...]"""
import glob
import json
import os
import sys


def load(d):
    out = {}
    for f in glob.glob(os.path.join(d, "*", "summary.json")):
        tag = os.path.basename(os.path.dirname(f))
        for method, v in json.load(open(f))["methods"].items():
            out[(tag, method)] = v
    return out


def cell(v):
    if v is None:
        return "-"
    focal = v.get("median_focal_err")
    focal = "" if focal is None else f", {100 * focal:.2f}%"
    return (f"{100 * v['auc@10']:.2f} ({100 * v['share_pose_err_above_5deg']:.1f}% > 5 deg{focal}"
            f", absurd {v.get('absurd_shifts', 0)})")


def main():
    dirs = sys.argv[1:]
    if not dirs:
        sys.exit(__doc__)
    sweeps = [load(d) for d in dirs]
    keys = sorted(set().union(*sweeps))
    print("| set | method | " + " | ".join(dirs) + " |")
    print("|---|---|" + "---|" * len(dirs))
    for k in keys:
        print(f"| {k[0]} | {k[1]} | " + " | ".join(cell(s.get(k)) for s in sweeps) + " |")
    for method in sorted({k[1] for k in keys}):
        common = [k for k in keys if k[1] == method and all(k in s for s in sweeps)]
        sums = [sum(100 * s[k]["auc@10"] for k in common) for s in sweeps]
        print(f"| sum of AUC@10 over {len(common)} sets | {method} | " + " | ".join(f"{x:.2f}" for x in sums) + " |")


if __name__ == "__main__":
    main()
