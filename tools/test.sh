#!/usr/bin/env bash
# Second README command: the whole test suite.
#  1. Release build: unit tests and the slow golden runs on ../shared data (label "slow").
#  2. AddressSanitizer + UndefinedBehaviorSanitizer build: the unit suite (label "unit").
#  3. ThreadSanitizer build: the tests that run the project's threads (tools/tsan.sh).
#  4. Fuzzing: the libFuzzer targets, 20 s each (tools/fuzz.sh; clang + ASan/UBSan).
# Set ESDSLAM_TEST_QUICK=1 to run only the Release unit suite.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
phase() { echo "test.sh: $1 done at $(( $(date +%s) - start )) s"; }
tools/build.sh release
phase "release build"
if [ "${ESDSLAM_TEST_QUICK:-0}" = "1" ]; then
  ctest --test-dir build -L unit --output-on-failure -j "$(nproc)"
  exit 0
fi
ctest --test-dir build --output-on-failure -j "$(nproc)"
phase "release tests (unit + slow)"
tools/build.sh asan
phase "ASan/UBSan build"
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan -L unit --output-on-failure -j "$(nproc)"
phase "ASan/UBSan unit tests"
tools/tsan.sh
phase "ThreadSanitizer build and tests"
tools/fuzz.sh
phase "fuzz build and runs"
