#pragma once
// What happened to one frame: the ONE per-frame report. Each stage returns its own value and the
// pipeline puts it in its slot, nothing is copied field by field:
//   run loop         index, timestamp, load_ms (time spent taking frames from the source),
//                    dropped_before (the source's count, RgbdFrame::dropped_before)
//   semantic stage   mask (SemanticFrontEnd::MaskFor, made ahead by MaskAhead; default in modes
//                    none and geometry), mask_wait_ms
//   SLAM system      track (SlamSystem::TrackRgbd), and inside it the geometry check's
//                    statistics (track.geometry, GeometryFilter::Apply's value)
//   pipeline         keypoints (counted from the tracked frame's flags), features, bgr
// Readers go through the column table (system/frame_columns.h: timing.csv, the summary, a
// viewer's stage times) or read the members directly (debug pictures, masks).
// Images and features are shared with the run (cv::Mat headers, shared_ptr): they are never
// written after the report is made, so a reader on another thread may keep them.

#include <cstdint>
#include <memory>

#include <opencv2/core.hpp>

#include "dynamic/semantic_front_end.h"
#include "map/feature_set.h"
#include "system/slam_system.h"

namespace esdslam {

struct KeypointCounts {
  int total = 0;
  int dynamic = 0;      // flagged dynamic, by the mask or by the geometry check
  int by_geometry = 0;  // of those, by the geometry check (kDynamicByGeometry)
};

KeypointCounts CountKeypoints(const FeatureSet& features);

struct FrameReport {
  std::int64_t index = 0;  // 0-based number of the frame in the run (the pipeline's frame id)
  double timestamp = 0;    // seconds
  double load_ms = 0;      // taking frames from the source during this frame's step (this frame's
                           // look-ahead successor; the first frame also counts its own;
                           // a live source: waiting for the frame to arrive)
  int dropped_before = 0;  // frames the source dropped just before this one (live playback, camera)
  DynamicMaskResult mask;  // the dynamic mask and its timings
  double mask_wait_ms = 0;  // tracking waited for the mask thread (dynamic/mask_ahead.h); 0 inline
  TrackOutcome track;      // extraction, tracking, state, pose, new keyframe, geometry check
  KeypointCounts keypoints;
  std::shared_ptr<const FeatureSet> features;  // the tracked frame's keypoints and is_dynamic flags
  cv::Mat bgr;                                 // the frame's colour image

  // Frames between this frame and the one whose labels made its mask; -1: no labels used.
  long label_age() const { return mask.source_id >= 0 ? static_cast<long>(index - mask.source_id) : -1; }
  const cv::Mat& geometry_mask() const { return track.geometry.mask; }  // empty when the check did not run
};

}  // namespace esdslam
