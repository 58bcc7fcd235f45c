#!/usr/bin/env bash
# The whole test suite: installs dependencies, builds, runs every test with ctest; then builds everything a
# second time with AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/) and runs the tests there too; then fuzzes the file parsers for a minute each (libFuzzer, scripts/fuzz.sh).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$ROOT/build}"
ASAN_DIR="${ASAN_DIR:-$ROOT/build-asan}"
bash "$ROOT/scripts/build.sh"
(cd "$BUILD_DIR" && ctest --output-on-failure -j "$(nproc)")

if [ "${MADSFM_SKIP_ASAN:-0}" != "1" ]; then
  echo "== sanitizers: every unit and CLI test again under ASan + UBSan ($ASAN_DIR; the e2e runs of colmap excepted)"
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$ROOT}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
  cmake -S "$ROOT" -B "$ASAN_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMADSFM_SANITIZE=ON \
    -DMADSFM_BUILD_BENCHMARKS=OFF >/dev/null
  cmake --build "$ASAN_DIR" -j "$(nproc)"
  (cd "$ASAN_DIR" && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --output-on-failure -j "$(nproc)" -E '^(e2e|python)/')
fi

if [ "${MADSFM_SKIP_FUZZ:-0}" != "1" ]; then
  echo "== fuzzing: libFuzzer on the .npy / depth-file / pair-directory / sparse-model / database-blob / shard-file parsers"
  bash "$ROOT/scripts/fuzz.sh" "${MADSFM_FUZZ_SECONDS:-60}"
fi
