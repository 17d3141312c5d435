#!/usr/bin/env bash
# Runs `esdslam run` several times per mode on one sequence and evaluates each trajectory with
# `esdslam eval`: prints one line per run (ATE RMSE in metres, frames tracked, fps) and the
# median ATE per mode. This is how the accuracy tables in docs/RESULTS.md are produced.
#
#   tools/ablation.sh SETTINGS SEQUENCE OUTDIR RUNS MODE... [-- EXTRA RUN ARGS]
#   e.g. tools/ablation.sh config/bonn.yaml ../shared/data/bonn_crowd_dev /tmp/abl 3 none full
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 5 ]; then
  sed -n 2,7p "$0" >&2
  exit 2
fi
settings=$1 sequence=$2 outdir=$3 runs=$4
shift 4
modes=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do modes+=("$1"); shift; done
[ "${1:-}" = "--" ] && shift
extra=("$@")
bin=${ESDSLAM_BIN:-build/esdslam}
mkdir -p "$outdir"
for mode in "${modes[@]}"; do
  ates=()
  for run in $(seq 1 "$runs"); do
    out="$outdir/$mode.$run"
    rm -rf "$out"
    "$bin" run --settings "$settings" --sequence "$sequence" --out "$out" --mode "$mode" "${extra[@]}" \
      > "$out.log" 2>&1 || { echo "run failed: $out.log" >&2; tail -5 "$out.log" >&2; exit 1; }
    ate=$("$bin" eval "$sequence/groundtruth.txt" "$out/trajectory.txt" | awk '$1 == "ate_rmse" {print $2}')
    tracked=$(awk '/^frames_tracked/ {print $2 "/" $4}' "$out.log")
    fps=$(awk '/^fps/ {print $2}' "$out.log")
    echo "$mode run $run: ate_rmse $ate tracked $tracked fps ${fps:-?}"
    ates+=("$ate")
  done
  median=$(printf '%s\n' "${ates[@]}" | sort -g | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}')
  echo "$mode median ate_rmse $median over $runs runs"
done
