#!/usr/bin/env bash
# The installed package as a user gets it (ctest Install.*; label slow):
#   1. `cmake --install BUILD --prefix` a fresh folder;
#   2. examples/track_tum configured with find_package(esdslam CONFIG) against it, built with the
#      shared and with the static library, and with pkg-config alone;
#   3. a synthetic dynamic sequence tracked by the installed `esdslam run --single-thread`, by the
#      example (shared; static with ESDSLAM_DATA_DIR) and by the installed Python module: the
#      trajectories are identical. Run from an empty folder: nothing is found in the source tree.
# Usage: tools/check_install.sh BUILD_DIR
set -euo pipefail
source_dir="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "$1" && pwd)"
work="$(mktemp -d /tmp/esdslam_install_XXXXXX)"
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
cd "$work"
cmake --install "$build" --prefix "$prefix" >/dev/null
generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
for variant in shared static; do
  static=OFF; [ "$variant" = static ] && static=ON
  cmake -S "$source_dir/examples/track_tum" -B "$work/example_$variant" "${generator[@]}" \
    -DCMAKE_PREFIX_PATH="$prefix" -DTRACK_TUM_STATIC=$static >/dev/null
  cmake --build "$work/example_$variant" >/dev/null
done
# pkg-config alone (shared library).
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
# shellcheck disable=SC2046
c++ -std=c++17 "$source_dir/examples/track_tum/main.cpp" -o "$work/track_tum_pc" $(pkg-config --cflags --libs esdslam) \
  $(pkg-config --libs opencv4)

"$prefix/bin/esdslam" synth --preset dynamic --frames 60 --out "$work/seq" >/dev/null 2>&1
settings="$work/seq/settings.yaml"
"$prefix/bin/esdslam" run --single-thread --settings "$settings" --sequence "$work/seq" --out "$work/cli" >/dev/null 2>&1
"$work/example_shared/track_tum" "$settings" "$work/seq" "$work/shared" --single-thread 2>/dev/null
ESDSLAM_DATA_DIR="$prefix/share/esdslam" "$work/example_static/track_tum" "$settings" "$work/seq" "$work/static" \
  --single-thread 2>/dev/null
LD_LIBRARY_PATH="$prefix/lib" "$work/track_tum_pc" "$settings" "$work/seq" "$work/pc" --single-thread 2>/dev/null
for out in shared static pc; do
  cmp "$work/cli/trajectory.txt" "$work/$out/trajectory.txt" || { echo "check_install: $out differs from the CLI"; exit 1; }
done
echo "check_install: the installed CLI, the example (shared, static, pkg-config) give the same trajectory"
module_dir="$prefix/lib/python3/dist-packages"
if ls "$module_dir"/esdslam*.so >/dev/null 2>&1; then
  PYTHONPATH="$module_dir" /usr/bin/python3 - "$work" <<'PY'
import sys, numpy as np
from PIL import Image
import esdslam
work = sys.argv[1]
slam = esdslam.System(work + "/seq/settings.yaml", single_thread=True, out_dir=work + "/python")
rgb = [l.split() for l in open(work + "/seq/rgb.txt") if l.strip() and not l.startswith("#")]
depth = [l.split() for l in open(work + "/seq/depth.txt") if l.strip() and not l.startswith("#")]
for (t, r), (_, d) in zip(rgb, depth):
    slam.track(np.asarray(Image.open(work + "/seq/" + r).convert("RGB")),
               np.asarray(Image.open(work + "/seq/" + d)).astype(np.uint16), float(t), rgb=True)
slam.shutdown()
PY
  cmp "$work/cli/trajectory.txt" "$work/python/trajectory.txt" || { echo "check_install: Python differs from the CLI"; exit 1; }
  echo "check_install: the installed Python module gives the same trajectory"
fi
