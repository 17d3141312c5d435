#!/usr/bin/env bash
# First README command: install dependencies, build (Release), and run the main job on the
# bundled example (a synthetic RGB-D sequence with moving people, generated deterministically),
# then evaluate its trajectory against the ground truth.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install_deps.sh
tools/build.sh release
example=out/example
rm -rf "$example"
./build/esdslam synth --preset dynamic --out "$example/sequence"
./build/esdslam run --settings "$example/sequence/settings.yaml" --sequence "$example/sequence" --out "$example/run"
./build/esdslam eval "$example/sequence/groundtruth.txt" "$example/run/trajectory.txt" --plot "$example/run/trajectory.svg"
echo "setup: example results in $example/run"
