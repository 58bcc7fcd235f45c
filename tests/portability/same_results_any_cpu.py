"""Same results on any x86-64 CPU (docs/robustness.md): `madsfm pair` on the example pairs, every camera mode, once
as the dynamic linker sets it up on this CPU and once with glibc's FMA/AVX2 code paths switched off (GLIBC_TUNABLES),
as on a CPU without them; every number of the JSON must be bit-identical. Then the same for `madsfm bench` (methods
hybrid and points: the 5-point / 7-point solvers too) on 20 synthetic two-focal pairs, every number of per_pair.csv.

    python3 same_results_any_cpu.py MADSFM LIBM_VARIANT_PROBE EXAMPLE_PAIRS_DIR WORK_DIR

The probe shows that the tunable really changes libm's ifunc choice here (else the comparison would prove nothing:
then, on a CPU without FMA/AVX2, the test says so and only checks that the two runs agree).
"""

import csv
import json
import math
import os
import shutil
import struct
import subprocess
import sys

# glibc 2.33+ names (2.26-2.32 spelled them AVX2_Usable, FMA_Usable, ...; the old names are silently ignored).
TUNABLES = "glibc.cpu.hwcaps=-AVX2,-AVX_Fast_Unaligned_Load,-FMA,-FMA4,-AVX512F"
PAIRS = ("1_eth3d", "2_2d3ds")
MODES = ("calibrated", "shared_focal", "two_focal")


def env(tunables):
    e = dict(os.environ)
    e.pop("GLIBC_TUNABLES", None)
    if tunables:
        e["GLIBC_TUNABLES"] = tunables
    return e


def run(cmd, tunables):
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env(tunables), timeout=300)
    if proc.returncode != 0:
        sys.exit(f"FAIL: {' '.join(cmd)} (GLIBC_TUNABLES={tunables or '-'}) exited {proc.returncode}: {proc.stderr}")
    return proc.stdout


def numbers(value, path=""):
    """Every number of a parsed JSON value by its path, runtime_ms left out; floats as their 64 bits."""
    if isinstance(value, dict):
        out = {}
        for k, v in value.items():
            if k != "runtime_ms":
                out.update(numbers(v, f"{path}/{k}"))
        return out
    if isinstance(value, list):
        out = {}
        for i, v in enumerate(value):
            out.update(numbers(v, f"{path}[{i}]"))
        return out
    if isinstance(value, float):
        return {path: struct.pack("<d", value).hex()}
    return {path: value}


def main(argv):
    if len(argv) != 5:
        sys.exit(__doc__)
    madsfm, probe, pairs_dir, work = argv[1:]
    default_probe, baseline_probe = run([probe], None).split(), run([probe], TUNABLES).split()
    print(f"libm on this CPU:           {' '.join(default_probe)}")
    print(f"libm with {TUNABLES}: {' '.join(baseline_probe)}")
    switched = default_probe != baseline_probe
    if not switched:
        print("NOTE: the tunable changes nothing on this CPU (no FMA/AVX2): both runs use the baseline libm")
    failures = 0
    for name in PAIRS:
        for mode in MODES:
            cmd = [madsfm, "pair", "--pair_path", os.path.join(pairs_dir, name), "--camera_mode", mode]
            a, b = json.loads(run(cmd, None)), json.loads(run(cmd, TUNABLES))
            if a["status"] != "ok":
                sys.exit(f"FAIL: {name} {mode}: status {a['status']}")
            na, nb = numbers(a), numbers(b)
            diff = sorted(k for k in na.keys() | nb.keys() if na.get(k) != nb.get(k))
            floats = sum(isinstance(v, float) for v in (a.get("R", []) + a.get("t", [])))
            if diff:
                failures += 1
                print(f"FAIL {name} {mode}: {len(diff)} of {len(na)} numbers differ, e.g.")
                for k in diff[:5]:
                    print(f"    {k}: {na.get(k)} vs {nb.get(k)}")
            else:
                print(f"ok   {name} {mode}: {len(na)} numbers bit-identical ({floats} in R and t)")
            assert math.isfinite(a["scale"])
    # Synthetic pairs (written once: the generator itself uses libm), estimated under both settings.
    shutil.rmtree(work, ignore_errors=True)
    run([madsfm, "synth", "--output_path", os.path.join(work, "pairs"), "--preset", "indoor_two_focal",
         "--num_pairs", "20", "--seed", "13"], None)
    rows = {}
    for label, tunables in (("default", None), ("baseline", TUNABLES)):
        out = os.path.join(work, label)
        run([madsfm, "bench", "--pairs_path", os.path.join(work, "pairs", "pairs.txt"), "--camera_mode", "two_focal",
             "--method", "hybrid,points", "--num_threads", "1", "--output_path", out], tunables)
        with open(os.path.join(out, "per_pair.csv")) as f:
            rows[label] = [{k: (float(v) if v and k not in ("pair", "method", "camera_mode", "status") else v)
                            for k, v in row.items() if k != "runtime_ms"} for row in csv.DictReader(f)]
    a, b = rows["default"], rows["baseline"]
    assert len(a) == 40 and sum(r["status"] == "ok" for r in a) >= 30, a
    differ = [(x, y) for x, y in zip(a, b) if numbers(x) != numbers(y)]
    if differ or len(a) != len(b):
        failures += 1
        print(f"FAIL bench: {len(differ)} of {len(a)} rows of per_pair.csv differ, e.g. {differ[:1]}")
    else:
        print(f"ok   bench two_focal hybrid+points on 20 synthetic pairs: {len(a)} rows bit-identical")
    if failures:
        sys.exit(f"FAIL: {failures} comparisons differ between the two libm variants")
    print("PASS")


if __name__ == "__main__":
    main(sys.argv)
