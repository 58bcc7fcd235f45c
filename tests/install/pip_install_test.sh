#!/usr/bin/env bash
# pip install --no-build-isolation of the repository into a temp --target dir (building _madsfm in this build tree,
# where it is up to date: nothing is recompiled), then `import madsfm` from there with PYTHONPATH = that dir only,
# one estimate, and pickling of the result. Offline: --no-index --no-deps (numpy is Debian's python3-numpy).
#   pip_install_test.sh PYTHON BUILD_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
PY="$1" BUILD="$2" SRC="$3" WORK="$4"
"$PY" -m pip --version >/dev/null 2>&1 || { echo "SKIPPED: no pip for $PY (Debian: apt-get install python3-pip)"; exit 77; }
[[ -n "$(ls "$BUILD"/python/madsfm/_madsfm*.so 2>/dev/null)" ]] || { echo "SKIPPED: this build has no Python module"; exit 77; }
rm -rf "$WORK"
mkdir -p "$WORK"
MADSFM_CMAKE_BUILD_DIR="$BUILD" "$PY" -m pip install --no-build-isolation --no-index --no-deps --no-cache-dir \
  --disable-pip-version-check --target "$WORK/site" "$SRC" >"$WORK/pip.log" 2>&1 ||
  { echo "FAIL: pip install:"; cat "$WORK/pip.log"; exit 1; }
ls "$WORK/site/madsfm"
cd "$WORK"
env -u PYTHONHOME PYTHONPATH="$WORK/site" PYTHONDONTWRITEBYTECODE=1 "$PY" - "$WORK/site" "$SRC" <<'PYEOF'
import os, pickle, sys
import numpy as np
import madsfm
import madsfm.pair
site, src = sys.argv[1:]
assert os.path.realpath(madsfm.__file__).startswith(os.path.realpath(site) + os.sep), madsfm.__file__
assert os.path.realpath(madsfm._madsfm.__file__).startswith(os.path.realpath(site) + os.sep)
d = os.path.join(src, "tests", "data", "example_pairs", "1_eth3d")
pair = madsfm.pair.read_pair(d)
r = madsfm.estimate_relative_pose(pair["kpts0"], pair["kpts1"], pair["depth0"], pair["depth1"], pair["K0"], pair["K1"],
                                  image_size0=pair["image_size0"], image_size1=pair["image_size1"])
assert r.success and r.num_inliers_sampson > 100, r
err = madsfm.rotation_error_deg(r.R, pair["T_0to1"][:3, :3])
assert err < 5, err
back = pickle.loads(pickle.dumps(r))
assert np.array_equal(back.R, r.R) and back.scale == r.scale and back.num_inliers_sampson == r.num_inliers_sampson
print(f"installed madsfm {madsfm.__version__} from {os.path.dirname(madsfm.__file__)}: {r.num_inliers_sampson} inliers, "
      f"rotation error {err:.3f} deg")
PYEOF
echo "PASS"
