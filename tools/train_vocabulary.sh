#!/usr/bin/env bash
# Re-creates models/vocabulary/orb_vocabulary.bin (see models/vocabulary/README.md).
# Usage: tools/train_vocabulary.sh [ESDSLAM_BINARY] [WORK_DIR]
# Needs ../shared/data/tum_fr1_rpy_dev. Deterministic: the output is byte-identical run to run.
set -euo pipefail
cd "$(dirname "$0")/.."
esdslam=${1:-build/esdslam}
work=${2:-$(mktemp -d)}
tum=../shared/data/tum_fr1_rpy_dev
[ -d "$tum" ] || { echo "missing $tum" >&2; exit 1; }
"$esdslam" synth --preset loop --frames 150 --out "$work/synth_loop"
"$esdslam" synth --preset static --frames 100 --seed 2 --out "$work/synth_static"
"$esdslam" vocab train --images "$tum" "$work/synth_loop" "$work/synth_static" \
  --k 10 --levels 5 --seed 1 --out models/vocabulary/orb_vocabulary.bin
