#!/usr/bin/env bash
# `cpack -G DEB` of this build tree, then `apt-get install ./madsfm_*.deb` (offline: its Depends are installed on any
# machine that built madsfm), the installed /usr/bin/madsfm runs --help and one pair, then `apt-get remove madsfm`.
# Root only (prints SKIPPED and exits 77 otherwise); a trap removes the package again whatever happens.
#   deb_package_test.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
BUILD="$1" SRC="$2" WORK="$3"
skip() { echo "SKIPPED: $*"; exit 77; }
# installed, not-installed, config-files, half-installed, ... (empty when dpkg never heard of madsfm).
status() { dpkg-query -W -f='${db:Status-Status}' madsfm 2>/dev/null || true; }
[[ "$(id -u)" -eq 0 ]] || skip "not root (apt-get install needs root)"
command -v apt-get >/dev/null && command -v dpkg-deb >/dev/null || skip "no apt-get / dpkg-deb (not Debian)"
# Someone's own madsfm package stays untouched.
if [[ -n "$(status)" && "$(status)" != not-installed ]]; then
  skip "a madsfm package is already known to dpkg ($(status))"
fi
[[ ! -e /usr/bin/madsfm ]] || skip "/usr/bin/madsfm exists and belongs to no madsfm package"
rm -rf "$WORK"
mkdir -p "$WORK"
cleanup() {
  if [[ -n "$(status)" && "$(status)" != not-installed ]]; then
    DEBIAN_FRONTEND=noninteractive apt-get purge -y -q madsfm >"$WORK/remove.log" 2>&1 ||
      { echo "FAIL: apt-get remove madsfm:"; cat "$WORK/remove.log"; }
  fi
}
trap cleanup EXIT

(cd "$WORK" && cpack -G DEB --config "$BUILD/CPackConfig.cmake" -B "$WORK") >"$WORK/cpack.log" 2>&1 ||
  { echo "FAIL: cpack:"; cat "$WORK/cpack.log"; exit 1; }
deb="$(ls "$WORK"/madsfm_*.deb)"
dev="$(ls "$WORK"/libmadsfm-dev_*.deb)"
echo "built $(basename "$deb") and $(basename "$dev")"
depends="$(dpkg-deb -f "$deb" Depends)"
echo "Depends: $depends"
echo "Recommends: $(dpkg-deb -f "$deb" Recommends)"
depends_names="$(tr ',' '\n' <<<"$depends" | awk '{print $1}')"
for p in libc6 libstdc++6 libsqlite3-0 zlib1g libpng16-16; do
  grep -Fxq "$p" <<<"$depends_names" || { echo "FAIL: Depends lacks $p"; exit 1; }
done
[[ "$(dpkg-deb -f "$deb" Recommends)" == *colmap* ]] || { echo "FAIL: colmap is not in Recommends"; exit 1; }
# The command package holds the command only.
contents="$(dpkg-deb -c "$deb" | awk '{print $6}')"
grep -qx './usr/bin/madsfm' <<<"$contents" || { echo "FAIL: no ./usr/bin/madsfm in $deb"; exit 1; }
if grep -q '\.a$\|\.h$' <<<"$contents"; then echo "FAIL: libraries or headers in $deb"; exit 1; fi
dev_contents="$(dpkg-deb -c "$dev")"
grep -q "usr/lib/cmake/madsfm/madsfmConfig.cmake" <<<"$dev_contents" || { echo "FAIL: no CMake package in $dev"; exit 1; }

DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "$deb" >"$WORK/install.log" 2>&1 ||
  { echo "FAIL: apt-get install $deb:"; cat "$WORK/install.log"; exit 1; }
/usr/bin/madsfm --help >"$WORK/help.txt" 2>&1 || { echo "FAIL: /usr/bin/madsfm --help"; cat "$WORK/help.txt"; exit 1; }
grep -q 'two_view_estimator' "$WORK/help.txt" || { echo "FAIL: --help does not list the commands"; exit 1; }
json="$(cd "$WORK" && /usr/bin/madsfm pair --pair_path "$SRC/tests/data/example_pairs/1_eth3d")"
python3 -c 'import json, sys; j = json.loads(sys.argv[1]); assert j["status"] == "ok", j; assert len(j["R"]) == 9' \
  "$json" || { echo "FAIL: /usr/bin/madsfm pair: $json"; exit 1; }
echo "/usr/bin/madsfm pair: status ok"
cleanup
if [[ -e /usr/bin/madsfm || ( -n "$(status)" && "$(status)" != not-installed ) ]]; then
  echo "FAIL: madsfm is still installed after apt-get remove"; exit 1
fi
echo "PASS"
