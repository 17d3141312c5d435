#include "viewer/viewer_options.h"

#include <fmt/format.h>

#include "common/data_files.h"
#include "common/error.h"

namespace esdslam {
namespace {

template <typename T>
void CheckOption(const char* name, T value, T min, T max) {
  if (value >= min && value <= max) return;
  throw Error(fmt::format("viewer: {} must be in [{}, {}], got {}", name, min, max, value));
}

}  // namespace

void ViewerOptions::Check() const {
  if (address.empty()) throw Error("viewer: the bind address is empty");
  if (web_dir.empty()) throw Error("viewer: the web folder is empty");
  CheckOption("port", port, 0, 65535);
  CheckOption("image scale", image_scale, 0.05, 1.0);
  CheckOption("JPEG quality", jpeg_quality, 1, 100);
  CheckOption("max keypoints", max_keypoints, 0, 20000);
  CheckOption("max map points", max_map_points, 0, 500000);
  CheckOption("max dynamic points", max_dynamic_points, 0, 100000);
  CheckOption("max dense points", max_dense_points, 0, 500000);
  CheckOption("max trajectory", max_trajectory, 2, 100000);
  CheckOption("frame interval (ms)", frame_interval_ms, 0.0, 10000.0);
  CheckOption("map interval (ms)", map_interval_ms, 10.0, 60000.0);
  CheckOption("dense interval (ms)", dense_interval_ms, 100.0, 600000.0);
  CheckOption("queue capacity", queue_capacity, std::size_t{1}, std::size_t{16});
}

std::string ViewerOptions::DefaultWebDir() { return FindDataPath("tools/web"); }

}  // namespace esdslam
