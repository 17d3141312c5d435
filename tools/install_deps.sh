#!/usr/bin/env bash
# Installs the Debian 12 packages ESD-SLAM needs to build, test and export models.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends \
  build-essential cmake ninja-build pkg-config git \
  libeigen3-dev libopencv-dev libceres-dev liboctomap-dev \
  libyaml-cpp-dev libspdlog-dev libfmt-dev libcli11-dev libtbb-dev \
  libgtest-dev libgmock-dev libbenchmark-dev libopenni2-dev libcpp-httplib-dev libdeflate-dev pybind11-dev python3-dev \
  clang libfuzzer-14-dev \
  python3 python3-numpy python3-torch python3-onnx python3-pil \
  chromium \
  >/dev/null
# The viewer page's three.js (tools/web/package-lock.json) from the npm registry, into
# tools/web/node_modules; esdslam serves it from there (nothing is fetched at run time).
if ! command -v npm >/dev/null 2>&1; then
  $SUDO apt-get install -y -qq --no-install-recommends npm >/dev/null
fi
npm ci --prefix "$(dirname "$0")/web" --no-audit --no-fund >/dev/null
echo "install_deps: done"
