#!/usr/bin/env python3
"""Share of runs with pose error max(rot, trans) > 5 deg (failures count), per method, from the CSV rows of the
anchor drivers (madpose_driver / poselib_driver --runs N) and of compare.sh's madsfm.csv; and the share of pairs
with at least one such run.  usage: stability.py CSV [CSV ...]"""
import csv
import sys
from collections import defaultdict


def main():
    runs = defaultdict(list)
    for path in sys.argv[1:]:
        with open(path) as f:
            for r in csv.DictReader(f):
                try:
                    e = max(float(r["rot_err_deg"]), float(r["trans_err_deg"]))
                except ValueError:
                    e = float("inf")
                if r["status"] != "ok":
                    e = float("inf")
                runs[r["method"]].append((r["pair"], e))
    print("| method | runs | pairs | runs > 5 deg | pairs with a run > 5 deg |")
    print("|---|---|---|---|---|")
    for method, rs in runs.items():
        pairs = defaultdict(list)
        for p, e in rs:
            pairs[p].append(e)
        bad_runs = sum(e > 5 for _, e in rs)
        bad_pairs = sum(any(e > 5 for e in es) for es in pairs.values())
        print(f"| {method} | {len(rs)} | {len(pairs)} | {100 * bad_runs / len(rs):.1f}% | "
              f"{100 * bad_pairs / len(pairs):.1f}% |")


if __name__ == "__main__":
    main()
