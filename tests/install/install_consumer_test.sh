#!/usr/bin/env bash
# `cmake --install` of this build tree into a fresh prefix, then tests/install/consumer (find_package(madsfm),
# madsfm::madsfm + madsfm::madsfm_colmap) configured, built and run against that prefix only; the installed
# madsfm binary runs one pair. Nothing of madsfm is rebuilt: the install copies the build tree's files.
#   install_consumer_test.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
BUILD="$1" SRC="$2" WORK="$3"
rm -rf "$WORK"
mkdir -p "$WORK"
PREFIX="$WORK/prefix"
cmake --install "$BUILD" --prefix "$PREFIX" >"$WORK/install.log"
for f in bin/madsfm lib/libmadsfm.a lib/libmadsfm_colmap.a include/madsfm/estimators/estimate_relpose.h \
         include/colmap_ext/database/database.h lib/cmake/madsfm/madsfmConfig.cmake \
         lib/cmake/madsfm/madsfmConfigVersion.cmake lib/cmake/madsfm/madsfmTargets.cmake; do
  [[ -e "$PREFIX/$f" ]] || { echo "FAIL: $PREFIX/$f was not installed"; exit 1; }
done
# No test, benchmark or fuzzer binary and no source file in the prefix.
if find "$PREFIX" -name '*_test' -o -name '*_bench' -o -name '*.cc' | grep -q .; then
  echo "FAIL: the install has files that do not belong there:"; find "$PREFIX" -name '*_test' -o -name '*_bench' -o -name '*.cc'
  exit 1
fi
# Only the prefix: no path into the source or build tree may leak into the consumer's configuration.
cmake -S "$SRC/tests/install/consumer" -B "$WORK/consumer" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$PREFIX" -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON >"$WORK/configure.log"
# (The prefix itself lies inside the build tree: its path is removed before looking for other paths into the trees.)
if sed "s|$PREFIX||g" "$WORK/consumer/CMakeFiles/consumer.dir/flags.make" | grep -qs -e "$SRC" -e "$BUILD"; then
  echo "FAIL: the consumer compiles against the source or build tree:"; cat "$WORK/consumer/CMakeFiles/consumer.dir/flags.make"
  exit 1
fi
cmake --build "$WORK/consumer" >"$WORK/build.log" || { cat "$WORK/build.log"; exit 1; }
out="$("$WORK/consumer/consumer")" || { echo "FAIL: consumer: $out"; exit 1; }
echo "consumer: $out"
json="$("$PREFIX/bin/madsfm" pair --pair_path "$SRC/tests/data/example_pairs/1_eth3d")"
python3 -c 'import json, sys; j = json.loads(sys.argv[1]); assert j["status"] == "ok", j' "$json" ||
  { echo "FAIL: installed madsfm pair: $json"; exit 1; }
echo "PASS"
