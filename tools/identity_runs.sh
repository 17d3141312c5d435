#!/usr/bin/env bash
# Single-thread reference runs for behaviour-preserving changes: runs `esdslam run --single-thread`
# on the synthetic presets and on both dev windows in ../shared/data, modes none and full, and
# writes each trajectory (and keyframes) under OUT. With --compare REF, checks that every
# trajectory is byte-identical to REF's and exits non-zero on the first difference.
#
#   tools/identity_runs.sh OUT [--compare REF] [--quick]
#     --quick: only the dynamic preset and both dev windows (what a refactor must keep first)
# ESDSLAM_BIN selects the binary (default build/esdslam). Synthetic sequences are cached in
# OUT/../identity_sequences (deterministic: the same binary version writes the same files).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: tools/identity_runs.sh OUT [--compare REF] [--quick]}
shift
ref="" quick=0
while [ $# -gt 0 ]; do
  case "$1" in
    --compare) ref=$2; shift 2 ;;
    --quick) quick=1; shift ;;
    *) echo "unknown argument $1" >&2; exit 2 ;;
  esac
done
bin=${ESDSLAM_BIN:-build/esdslam}
shared=${ESDSLAM_SHARED:-../shared}
seqs="$(dirname "$out")/identity_sequences"
mkdir -p "$out" "$seqs"
presets=(dynamic)
[ "$quick" = 1 ] || presets=(static dynamic orbit loop corridor)
cases=()
for preset in "${presets[@]}"; do
  if [ ! -f "$seqs/$preset/groundtruth.txt" ]; then
    "$bin" synth --preset "$preset" --out "$seqs/$preset" > /dev/null 2>&1
  fi
  cases+=("$preset|$seqs/$preset/settings.yaml|$seqs/$preset")
done
[ -d "$shared/data/bonn_crowd_dev" ] && cases+=("bonn|config/bonn.yaml|$shared/data/bonn_crowd_dev")
[ -d "$shared/data/tum_fr1_rpy_dev" ] && cases+=("fr1|config/tum_fr1.yaml|$shared/data/tum_fr1_rpy_dev")
status=0
for entry in "${cases[@]}"; do
  IFS='|' read -r name settings sequence <<< "$entry"
  for mode in none full; do
    run="$out/$name.$mode"
    rm -rf "$run"
    "$bin" run --settings "$settings" --sequence "$sequence" --out "$run" --mode "$mode" --single-thread \
      > "$run.log" 2>&1 || { echo "$name $mode: run failed ($run.log)"; status=1; continue; }
    if [ -n "$ref" ]; then
      if cmp -s "$run/trajectory.txt" "$ref/$name.$mode/trajectory.txt" &&
         cmp -s "$run/keyframes.txt" "$ref/$name.$mode/keyframes.txt"; then
        echo "$name $mode: identical"
      else
        echo "$name $mode: DIFFERENT from $ref"
        status=1
      fi
    else
      echo "$name $mode: $(wc -l < "$run/trajectory.txt") poses"
    fi
  done
done
exit $status
