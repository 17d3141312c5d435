#pragma once
// One `esdslam run` over a TUM-layout sequence with the dynamic stages switched by a mode:
//   none      plain ORB-SLAM2-style RGB-D SLAM
//   semantic  segmentation (dynamic classes) + depth region growing -> dynamic mask per frame
//   geometry  multi-view geometry check in tracking only (no network)
//   full      both: the semantic mask first, then the geometry check on potentially dynamic
//             class regions and unlabelled (background) regions; labelled static classes and
//             the semantic mask are exempt from it (Frame::geometry_exempt)
// Per frame (Step): load frame i (frame i+1 is loaded and submitted to the segmentation thread
// before frame i is tracked, so the network runs in parallel with extraction and tracking), take
// frame i's dynamic mask, track with it (the extractor spends its budget on the static area; the
// geometry check runs inside tracking), hand new keyframes to the dense mapper (depth masked by
// the semantic and the geometry masks), write the debug picture.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "dense/dense_mapper.h"
#include "dense/slam_keyframe_poses.h"
#include "io/tum_sequence.h"
#include "system/run_settings.h"
#include "dynamic/semantic_front_end.h"
#include "system/slam_system.h"

namespace esdslam {

enum class DynamicMode { kNone, kSemantic, kGeometry, kFull };
const char* ToString(DynamicMode mode);
DynamicMode ParseDynamicMode(const std::string& text);  // throws Error

bool UsesSegmentation(DynamicMode mode);
bool UsesGeometryCheck(DynamicMode mode);

struct DynamicRunOptions {
  DynamicMode mode = DynamicMode::kFull;
  bool realtime = false;         // newest-wins segmentation (overrides Semantic.realtime)
  bool dense = false;            // dense map of the keyframes, written by Finish
  std::string dense_mask_dir;    // with dense: each keyframe's dynamic mask saved as <timestamp>.png; empty = not saved
  std::string debug_frames_dir;  // per-frame PNG with kept/removed keypoints; empty = off
  bool threaded_dense = true;
  // Give the extractor the static area only (its budget is not spent on movers). Off: keypoints
  // are extracted everywhere and the ones on the mask are flagged dynamic (tests measure that).
  bool mask_extraction = true;
};

struct FrameStep {
  double timestamp = 0;
  double load_ms = 0;     // reading frame i's images (or the look-ahead frame's)
  TrackOutcome outcome;
  DynamicMaskResult mask;  // empty in modes none and geometry
  cv::Mat geometry_mask;   // CV_8U, 255 = moving by the geometry check; empty when it did not run
  int keypoints = 0, dynamic_keypoints = 0;  // dynamic: by the mask or by geometry
  int geometry_keypoints = 0;                // of those, by geometry
};

class DynamicRun {
 public:
  // frames: the sequence's frames to process, in order (kept by reference).
  DynamicRun(const RunSettings& settings, const SlamOptions& slam_options, const DynamicRunOptions& options,
             const std::vector<FrameEntry>& frames);
  ~DynamicRun();

  FrameStep Step(std::size_t i);  // i must advance by one from 0
  // Stops the threads; with dense, writes dir/dense.ply, octomap.bt, dense_top.png,
  // dense_view.png and dense_keyframes.txt (every dense keyframe, culled ones included) at the
  // keyframes' final poses.
  void Finish(const std::string& out_dir);

  SlamSystem& system() { return *system_; }
  // Null without dense. Thread-safe on-demand builds at the current keyframe poses.
  const DenseMapper* dense() const { return dense_.get(); }
  const SemanticFrontEnd* semantic() const { return semantic_.get(); }

 private:
  RgbdImages Load(std::size_t i, double* load_ms);
  void AddDenseKeyframe(std::size_t i, const RgbdImages& images, const cv::Mat& mask, KeyFrame* keyframe);
  void WriteDebugFrame(const FrameStep& step, const RgbdImages& images) const;

  RunSettings settings_;
  DynamicRunOptions options_;
  const std::vector<FrameEntry>& frames_;
  std::unique_ptr<SemanticFrontEnd> semantic_;
  std::unique_ptr<SlamSystem> system_;
  std::unique_ptr<SlamKeyframePoses> dense_poses_;  // before dense_: its worker reads them
  std::unique_ptr<DenseMapper> dense_;
  std::optional<std::pair<std::size_t, RgbdImages>> next_;  // frame loaded (and submitted) ahead
  bool finished_ = false;
};

}  // namespace esdslam
