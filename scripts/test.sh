#!/usr/bin/env bash
# The whole test suite: installs dependencies, builds, runs every test with ctest; then builds the core
# library and its unit tests a second time with AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/)
# and runs them there too; then fuzzes the file parsers for a minute each (libFuzzer, scripts/fuzz.sh).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$ROOT/build}"
ASAN_DIR="${ASAN_DIR:-$ROOT/build-asan}"
bash "$ROOT/scripts/build.sh"
(cd "$BUILD_DIR" && ctest --output-on-failure -j "$(nproc)")

if [ "${MADSFM_SKIP_ASAN:-0}" != "1" ]; then
  echo "== sanitizers: ASan + UBSan build of the core library and its unit tests ($ASAN_DIR)"
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$ROOT}"
  cmake -S "$ROOT" -B "$ASAN_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMADSFM_SANITIZE=ON \
    -DMADSFM_BUILD_BENCHMARKS=OFF >/dev/null
  cmake --build "$ASAN_DIR" -j "$(nproc)" --target madsfm_solvers_test madsfm_geometry_test \
    madsfm_refinement_test madsfm_estimators_test madsfm_io_test colmap_ext_database_test colmap_ext_camera_test
  (cd "$ASAN_DIR" && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --output-on-failure -j "$(nproc)" \
    -R '^(madsfm/(solvers|geometry|refinement|estimators|io)|colmap_ext/(database|camera))/')
fi

if [ "${MADSFM_SKIP_FUZZ:-0}" != "1" ]; then
  echo "== fuzzing: libFuzzer on the .npy / depth-file / pair-directory / sparse-model / database-blob parsers"
  bash "$ROOT/scripts/fuzz.sh" "${MADSFM_FUZZ_SECONDS:-60}"
fi
