#include "system/frame_columns.h"

#include <fmt/format.h>

#include "common/error.h"

namespace esdslam {
namespace {

using R = const FrameReport&;
constexpr int kInt = FrameColumn::kInteger;

const char* StateName(double value) { return ToString(static_cast<TrackingState>(static_cast<int>(value))); }

// The geometry check's depth window radius; -1 when it skipped the frame (too fast).
double WindowPx(R r) { return r.track.geometry.skipped_fast_motion ? -1 : r.track.geometry.window_radius_px; }

}  // namespace

// The table. Times are wall-clock milliseconds unless named *_cpu_ms (CPU time of the thread).
const std::vector<FrameColumn>& FrameColumns() {
  static const std::vector<FrameColumn> columns = {
    {"timestamp", "s", 6, [](R r) { return r.timestamp; }},
    {"load_ms", "ms", 3, [](R r) { return r.load_ms; }, "load"},
    {"extract_ms", "ms", 3, [](R r) { return r.track.extract_ms; }, "extract"},
    {"track_ms", "ms", 3, [](R r) { return r.track.track_ms; }, "track"},
    {"state", "", kInt, [](R r) { return static_cast<double>(r.track.state); }, nullptr, true, StateName},
    {"lost", "", kInt, [](R r) { return r.track.has_pose ? 0.0 : 1.0; }},
    {"seg_latency_ms", "ms", 3, [](R r) { return r.mask.latency_ms; }, "seg_lat"},
    {"seg_wait_ms", "ms", 3, [](R r) { return r.mask.wait_ms; }, "seg_wait"},
    {"mask_ms", "ms", 3, [](R r) { return r.mask.refine_ms; }, "mask"},
    {"label_age", "frames", kInt, [](R r) { return static_cast<double>(r.label_age()); }},
    {"dynamic_fraction", "", 4, [](R r) { return r.mask.dynamic_fraction; }},
    {"keypoints", "", kInt, [](R r) { return static_cast<double>(r.keypoints.total); }},
    {"dynamic_keypoints", "", kInt, [](R r) { return static_cast<double>(r.keypoints.dynamic); }},
    {"grow_ms", "ms", 3, [](R r) { return r.mask.grow_ms; }, "grow"},
    {"geometry_ms", "ms", 3, [](R r) { return r.track.geometry.check_ms; }, "geometry"},
    {"geometry_keypoints", "", kInt, [](R r) { return static_cast<double>(r.keypoints.by_geometry); }},
    {"geometry_culled", "", kInt, [](R r) { return static_cast<double>(r.track.geometry.points_culled); }},
    {"geometry_covered", "", kInt, [](R r) { return static_cast<double>(r.track.geometry.covered); }},
    {"geometry_window_px", "px", kInt, WindowPx},
    {"grow_cpu_ms", "ms", 3, [](R r) { return r.mask.grow_cpu_ms; }},
    {"geometry_cpu_ms", "ms", 3, [](R r) { return r.track.geometry.check_cpu_ms; }},
    // Frames the source dropped just before this one (live playback, a camera); 0 from a folder.
    {"dropped_before", "frames", kInt, [](R r) { return static_cast<double>(r.dropped_before); }},
    // Predicted masks (dynamic/semantic_front_end.h): the optical flow and carrying, and the trust.
    {"predict_ms", "ms", 3, [](R r) { return r.mask.predict_ms; }, "predict"},
    {"predict_cpu_ms", "ms", 3, [](R r) { return r.mask.predict_cpu_ms; }},
    {"label_trust", "", 3, [](R r) { return r.mask.trust; }},
    // Tracking waited for the mask thread (the mask of a frame is made ahead, dynamic/mask_ahead.h).
    {"mask_wait_ms", "ms", 3, [](R r) { return r.mask_wait_ms; }, "mask_wait"},
    // Map points the tracked pose rests on (local-map inliers; 0 without a pose), and whether the
    // frame became a keyframe.
    {"inliers", "", kInt, [](R r) { return static_cast<double>(r.track.has_pose ? r.track.inliers : 0); }},
    {"new_keyframe", "", kInt, [](R r) { return r.track.new_keyframe ? 1.0 : 0.0; }},
    // A blind frame (blocked sensor, view filled by people) given the motion model's pose.
    {"coasted", "", kInt, [](R r) { return r.track.coasted ? 1.0 : 0.0; }},
    // Summary only: the dynamic stages together (region growing + geometry check).
    {"dynamic_ms", "ms", 3, [](R r) { return r.mask.grow_ms + r.track.geometry.check_ms; }, "grow+geo", false},
    {"dynamic_cpu_ms", "ms", 3, [](R r) { return r.mask.grow_cpu_ms + r.track.geometry.check_cpu_ms; }, "(cpu)",
     false},
  };
  return columns;
}

std::string FrameColumn::Format(double value) const {
  if (text != nullptr) return text(value);
  if (decimals == kInteger) return fmt::format("{}", static_cast<long long>(value));
  return fmt::format("{:.{}f}", value, decimals);
}

std::size_t FrameColumnIndex(const std::string& name) {
  const std::vector<FrameColumn>& columns = FrameColumns();
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (name == columns[i].name) return i;
  throw Error("no per-frame column named '" + name + "'");
}

const FrameColumn& FindFrameColumn(const std::string& name) { return FrameColumns()[FrameColumnIndex(name)]; }

std::string FrameCsvHeader() {
  std::string header;
  for (const FrameColumn& column : FrameColumns())
    if (column.csv) header += (header.empty() ? "" : ",") + std::string(column.name);
  return header;
}

std::string FrameCsvRow(const std::vector<double>& values) {
  const std::vector<FrameColumn>& columns = FrameColumns();
  if (values.size() != columns.size())
    throw Error(fmt::format("frame row has {} values for {} columns", values.size(), columns.size()));
  std::string row;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (!columns[i].csv) continue;
    if (!row.empty()) row += ',';
    row += columns[i].Format(values[i]);
  }
  return row;
}

std::vector<double> ReadFrameColumns(const FrameReport& report) {
  std::vector<double> values;
  values.reserve(FrameColumns().size());
  for (const FrameColumn& column : FrameColumns()) values.push_back(column.read(report));
  return values;
}

}  // namespace esdslam
