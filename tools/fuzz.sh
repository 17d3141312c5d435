#!/usr/bin/env bash
# Fuzzing: builds the libFuzzer targets of fuzz/ with clang (AddressSanitizer +
# UndefinedBehaviorSanitizer) in build-fuzz and runs each for ESDSLAM_FUZZ_SECONDS (default 20)
# from a corpus seeded with real files: the shipped settings and ORB-SLAM2/3 examples, the
# association file and lists derived from it, a trajectory, and a map and a vocabulary written
# by the library. Any crash, hang (> 10 s per input), leak, sanitizer report or allocation over
# 2 GB fails the script; the input is kept in build-fuzz/findings/<target>/.
# Usage: tools/fuzz.sh [target ...]   (targets: settings sequence_lists trajectory map_file vocabulary png)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${ESDSLAM_FUZZ_SECONDS:-20}"
jobs="${ESDSLAM_JOBS:-$(nproc)}"
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(settings sequence_lists trajectory map_file vocabulary png)
flags="-O1 -g1 -fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=undefined"
args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=$flags"
      -DESDSLAM_BUILD_TESTS=OFF -DESDSLAM_BUILD_BENCHMARKS=OFF -DESDSLAM_BUILD_FUZZERS=ON)
if command -v ccache >/dev/null 2>&1; then
  args+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$(cd .. && pwd)}"
  export CCACHE_SLOPPINESS="${CCACHE_SLOPPINESS:-pch_defines,time_macros,include_file_mtime,include_file_ctime}"
fi
if command -v ninja >/dev/null 2>&1 && { [ ! -f build-fuzz/CMakeCache.txt ] || grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' build-fuzz/CMakeCache.txt; }; then
  args+=(-G Ninja)
fi
cmake -S . -B build-fuzz "${args[@]}" >/dev/null
cmake --build build-fuzz -j "$jobs" --target "${targets[@]/%/_fuzzer}"

seeds=build-fuzz/seeds
rm -rf "$seeds" build-fuzz/corpus
mkdir -p "$seeds"/{settings,sequence_lists,trajectory,map_file,vocabulary,png}
cp config/*.yaml tests/data/orbslam/*.yaml "$seeds/settings/"
associations=tests/data/orbslam/fr1_rpy_dev_associations.txt
# sequence_lists: the first byte picks the file (0 rgb.txt, 1 depth.txt, 2 association file).
{ printf '\000# rgb\n'; head -40 "$associations" | awk '{print $1, $2}'; } > "$seeds/sequence_lists/rgb.txt"
{ printf '\001# depth\n'; head -40 "$associations" | awk '{print $3, $4}'; } > "$seeds/sequence_lists/depth.txt"
{ printf '\002'; head -40 "$associations"; } > "$seeds/sequence_lists/associations.txt"
# trajectory: TUM format 'timestamp tx ty tz qx qy qz qw', from the association stamps.
head -60 "$associations" | awk '{printf "%s %.4f 0.0100 -0.0200 0 0 %.4f 1\n", $1, NR * 0.01, NR * 0.001}' \
  > "$seeds/trajectory/trajectory.txt"
ESDSLAM_FUZZ_WRITE_SEED="$seeds/map_file/map.bin" build-fuzz/fuzz/map_file_fuzzer 2>/dev/null || true
ESDSLAM_FUZZ_WRITE_SEED="$seeds/vocabulary/vocabulary.bin" build-fuzz/fuzz/vocabulary_fuzzer 2>/dev/null || true
ESDSLAM_FUZZ_WRITE_SEED="$seeds/png" build-fuzz/fuzz/png_fuzzer 2>/dev/null || true

status=0
for target in "${targets[@]}"; do
  corpus="build-fuzz/corpus/$target"
  findings="build-fuzz/findings/$target"
  mkdir -p "$corpus" "$findings"
  if ! ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
      "build-fuzz/fuzz/${target}_fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      -max_len=65536 -print_final_stats=1 -artifact_prefix="$findings/" "$corpus" "$seeds/$target" \
      > "build-fuzz/$target.log" 2>&1; then
    echo "fuzz.sh: $target FAILED (input in $findings/, log build-fuzz/$target.log)"
    tail -40 "build-fuzz/$target.log"
    status=1
  else
    echo "fuzz.sh: $target ok: $(grep -o 'stat::number_of_executed_units: *[0-9]*' "build-fuzz/$target.log" | grep -o '[0-9]*$') inputs in ${seconds} s"
  fi
done
exit $status
