#!/usr/bin/env python3
"""Adds random outlier matches to every matched pair of a COLMAP database and re-runs COLMAP's geometric
verification on them (colmap matches_importer --match_type raw), so that COLMAP and madsfm both start from raw
matches with at least RATIO outliers.

Usage: add_outlier_matches.py DATABASE RATIO SEED [COLMAP]
Per pair with n raw matches, round(n * RATIO / (1 - RATIO)) matches between uniformly drawn keypoints are added
(the raw matches hold some outliers of their own, so the final outlier ratio is at least RATIO). The matches and
two_view_geometries tables are emptied and rebuilt by matches_importer (in the database's own transactions).
Prints the outlier ratio of the new raw matches as measured by COLMAP's verification: 1 - inliers / matches.
"""
import array
import os
import random
import sqlite3
import subprocess
import sys
import tempfile

K = 2147483647


def blob_u32(blob):
    a = array.array("I")
    a.frombytes(blob)
    return a


def main():
    db_path, ratio, seed = sys.argv[1], float(sys.argv[2]), int(sys.argv[3])
    colmap = sys.argv[4] if len(sys.argv) > 4 else "colmap"
    if not 0.0 <= ratio < 1.0:
        sys.exit(f"{sys.argv[0]}: RATIO must be in [0, 1), got {ratio}")
    rng = random.Random(seed)
    con = sqlite3.connect(db_path)
    names = dict(con.execute("SELECT image_id, name FROM images"))
    nkp = dict(con.execute("SELECT image_id, rows FROM keypoints"))
    rows = con.execute("SELECT pair_id, rows, data FROM matches WHERE rows > 0 ORDER BY pair_id").fetchall()
    with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as f:
        path = f.name
        total = 0
        for pair_id, n, data in rows:
            i2 = pair_id % K
            i1 = (pair_id - i2) // K
            m = blob_u32(data)
            pairs = [(m[2 * k], m[2 * k + 1]) for k in range(n)]
            for _ in range(round(n * ratio / (1.0 - ratio))):
                pairs.append((rng.randrange(nkp[i1]), rng.randrange(nkp[i2])))
            rng.shuffle(pairs)
            total += len(pairs)
            f.write(f"{names[i1]} {names[i2]}\n")
            f.writelines(f"{a} {b}\n" for a, b in pairs)
            f.write("\n")
    with con:
        con.execute("DELETE FROM matches")
        con.execute("DELETE FROM two_view_geometries")
    con.close()
    log = db_path + ".outliers.log"
    with open(log, "w") as lf:
        rc = subprocess.call([colmap, "matches_importer", "--database_path", db_path, "--match_list_path", path,
                              "--match_type", "raw", "--SiftMatching.use_gpu", "0"], stdout=lf, stderr=subprocess.STDOUT)
    os.unlink(path)
    if rc != 0:
        sys.exit(f"{sys.argv[0]}: colmap matches_importer failed (exit {rc}); log {log}")
    con = sqlite3.connect(db_path)
    matches = con.execute("SELECT COALESCE(SUM(rows), 0) FROM matches").fetchone()[0]
    inliers = con.execute("SELECT COALESCE(SUM(rows), 0) FROM two_view_geometries").fetchone()[0]
    con.close()
    print(f"outliers: {len(rows)} pairs, {matches} raw matches (was {total} written), "
          f"outlier ratio {1.0 - inliers / max(matches, 1):.3f} (1 - COLMAP inliers / raw matches)")


if __name__ == "__main__":
    main()
