#!/usr/bin/env bash
# libFuzzer runs of madsfm's file parsers (tests/fuzz/*_fuzzer.cc): builds them with clang (ASan + UBSan +
# libFuzzer) in build-fuzz/, writes seed corpora from tests/data/example_pairs, and runs every fuzzer for
# SECONDS_PER_TARGET seconds (default 60). With 0, each fuzzer only runs its seeds and the saved reproducers of
# tests/fuzz/crashes/ once (a quick regression check for the test suite).
# Crashes are saved as tests/fuzz/crashes/<fuzzer>-crash-<sha1> (or leak-, oom-, timeout-). Exits non-zero if
# any fuzzer failed. Environment: FUZZ_BUILD_DIR, FUZZERS (space-separated subset), CXX (default clang++).
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SECONDS_PER_TARGET="${1:-60}"
BUILD_DIR="${FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$ROOT}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"  # cache hits from any clone
CRASH_DIR="$ROOT/tests/fuzz/crashes"
ALL_FUZZERS="npy_fuzzer depth_file_fuzzer pair_directory_fuzzer sparse_model_fuzzer database_blob_fuzzer shard_file_fuzzer"
FUZZERS="${FUZZERS:-$ALL_FUZZERS}"

cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER="${CXX:-clang++}" \
  -DMADSFM_FUZZ=ON -DMADSFM_BUILD_TESTS=OFF -DMADSFM_BUILD_BENCHMARKS=OFF -DMADSFM_NATIVE=OFF >/dev/null || exit 2
# shellcheck disable=SC2086
cmake --build "$BUILD_DIR" -j "$(nproc)" --target $FUZZERS || exit 2

CORPUS="$BUILD_DIR/fuzz_corpus"
rm -rf "$CORPUS/seeds"
python3 "$ROOT/tests/fuzz/make_seeds.py" "$CORPUS/seeds" "$ROOT/tests/data/example_pairs" || exit 2
mkdir -p "$CRASH_DIR"

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
COMMON=(-max_len=4096 -rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=10 -print_final_stats=1)

status=0
summary=""
for f in $FUZZERS; do
  log="$BUILD_DIR/$f.log"
  mkdir -p "$CORPUS/work/$f"
  start=$(date +%s)
  if [ "$SECONDS_PER_TARGET" = "0" ]; then
    # Individual files (libFuzzer runs each once and stops at the first failure).
    inputs=("$CORPUS/seeds/$f"/*)
    for c in "$CRASH_DIR/$f"-*; do [ -f "$c" ] && inputs+=("$c"); done
    "$BUILD_DIR/$f" "${COMMON[@]}" "${inputs[@]}" >"$log" 2>&1
  else
    "$BUILD_DIR/$f" "${COMMON[@]}" -max_total_time="$SECONDS_PER_TARGET" -artifact_prefix="$CRASH_DIR/$f-" \
      "$CORPUS/work/$f" "$CORPUS/seeds/$f" >"$log" 2>&1
  fi
  rc=$?
  secs=$(($(date +%s) - start))
  if [ "$SECONDS_PER_TARGET" = "0" ]; then
    runs="$(grep -c '^Executed ' "$log")"
  else
    runs="$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | tail -1 | awk '{print $2}')"
  fi
  if [ $rc -eq 0 ]; then
    result="ok"
  else
    status=1
    artifact="$(grep -o "Test unit written to .*" "$log" | tail -1 | sed 's/Test unit written to //')"
    reason="$(grep -m1 -E 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:|ALARM' "$log" | cut -c1-160)"
    result="FAILED (exit $rc): ${reason:-see log}${artifact:+; reproducer $artifact}"
    echo "== $f: last 40 lines of $log"
    tail -40 "$log"
  fi
  summary+="$(printf '%-24s runs %-10s seconds %-6s %s' "$f" "${runs:-?}" "${secs:-?}" "$result")"$'\n'
done
echo "== fuzz summary (${SECONDS_PER_TARGET}s per target; logs in $BUILD_DIR/*.log)"
printf '%s' "$summary"
exit $status
