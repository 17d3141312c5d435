#!/usr/bin/env bash
# Configures and builds one build tree. Usage: tools/build.sh [release|asan|tsan|debug]
# (ESDSLAM_JOBS: parallel jobs, default nproc; ESDSLAM_BUILD_TARGETS: targets, default all)
set -euo pipefail
cd "$(dirname "$0")/.."
kind="${1:-release}"
jobs="${ESDSLAM_JOBS:-$(nproc)}"
# Sanitizer builds: -O1 with line tables only (fast to compile, enough for the reports' stack
# traces), no benchmarks and no slow tests (they only run the unit suite), no OpenNI2 source.
sanitizer_args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1"
                -DESDSLAM_BUILD_BENCHMARKS=OFF -DESDSLAM_BUILD_SLOW_TESTS=OFF
                -DESDSLAM_OPENNI2=OFF)  # OpenNI2's drivers leak on shutdown (CMakeLists.txt)
case "$kind" in
  release) dir=build;      args=(-DCMAKE_BUILD_TYPE=Release) ;;
  asan)    dir=build-asan; args=("${sanitizer_args[@]}" -DESDSLAM_SANITIZE=address,undefined) ;;
  tsan)    dir=build-tsan; args=("${sanitizer_args[@]}" -DESDSLAM_SANITIZE=thread) ;;
  debug)   dir=build-debug; args=(-DCMAKE_BUILD_TYPE=Debug) ;;
  *) echo "usage: tools/build.sh [release|asan|tsan|debug]" >&2; exit 2 ;;
esac
# ccache, when installed, shares compiled objects between checkouts (CCACHE_BASEDIR makes the
# paths relative); CI machines without it build as usual.
if command -v ccache >/dev/null 2>&1; then
  args+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$(cd .. && pwd)}"
  # Objects compiled with the precompiled headers (CMakeLists.txt ESDSLAM_PCH) are cached only
  # with these.
  export CCACHE_SLOPPINESS="${CCACHE_SLOPPINESS:-pch_defines,time_macros,include_file_mtime,include_file_ctime}"
fi
# Ninja when installed (tools/install_deps.sh installs it): it keeps both cores busy across the
# stage libraries. A build tree configured earlier keeps its generator.
if command -v ninja >/dev/null 2>&1 && { [ ! -f "$dir/CMakeCache.txt" ] || grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$dir/CMakeCache.txt"; }; then
  args+=(-G Ninja)
fi
cmake -S . -B "$dir" "${args[@]}" >/dev/null
# ESDSLAM_BUILD_TARGETS: space-separated targets to build instead of all.
read -r -a targets <<< "${ESDSLAM_BUILD_TARGETS:-all}"
cmake --build "$dir" -j "$jobs" --target "${targets[@]}"
