#!/usr/bin/env bash
# Installs dependencies if needed, configures and builds madsfm (Release) into ${BUILD_DIR:-build}.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$ROOT/build}"
# Cache hits across clones at different paths (CI builds a fresh clone).
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$ROOT}"
# Debug builds (-g: the sanitizer and fuzzer builds) would otherwise hash the build folder's absolute path, so a
# clone elsewhere would miss the cache; only the compile directory recorded in the debug info is affected.
export CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
bash "$ROOT/scripts/install_deps.sh"
cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$BUILD_DIR" -j "$(nproc)"
