#!/usr/bin/env bash
# Configures and builds one build tree. Usage: tools/build.sh [release|asan|tsan|debug]
set -euo pipefail
cd "$(dirname "$0")/.."
kind="${1:-release}"
jobs="${ESDSLAM_JOBS:-$(nproc)}"
case "$kind" in
  release) dir=build;      args=(-DCMAKE_BUILD_TYPE=Release) ;;
  asan)    dir=build-asan; args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DESDSLAM_SANITIZE=address,undefined -DESDSLAM_BUILD_BENCHMARKS=OFF) ;;
  tsan)    dir=build-tsan; args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DESDSLAM_SANITIZE=thread -DESDSLAM_BUILD_BENCHMARKS=OFF) ;;
  debug)   dir=build-debug; args=(-DCMAKE_BUILD_TYPE=Debug) ;;
  *) echo "usage: tools/build.sh [release|asan|tsan|debug]" >&2; exit 2 ;;
esac
cmake -S . -B "$dir" "${args[@]}" >/dev/null
cmake --build "$dir" -j "$jobs"
