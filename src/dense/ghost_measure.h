#pragma once
// The ghost measure of a finished map: how much of it a camera sees straight through.
//
// Every map point (or occupied OctoMap cell centre) is projected into a frame at that frame's
// pose (world_from_cam, e.g. the run's trajectory) and compared with the depth the frame measured
// at the pixel it lands on (nearest pixel of the raw, distorted depth image). A projection counts
// when the pixel has a valid depth; it is "seen through" when the measured depth exceeds the
// point's depth along the optical axis by more than `margin_m`: the ray reached farther, so the
// space where the map holds the point was observed empty. A person walking in front of a point
// (measured depth smaller) is not a ghost.
//
//   fraction = seen-through projections / counted projections, over the frames measured.
//
// Per point, the number of frames that saw through it is kept, so persistent ghosts (seen through
// by `persistent_frames` or more frames) can be counted and drawn.

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "common/error.h"
#include "dense/point_cloud.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"

namespace esdslam {

struct GhostMeasureOptions {
  double margin_m = 0.15;     // m: measured depth beyond the point's depth by more than this = seen through
  int frame_step = 10;        // every k-th pose of the trajectory is a measured frame
  int persistent_frames = 5;  // a point seen through by this many frames is a persistent ghost
  double max_pose_dt = 0.02;  // s: a trajectory pose and its sequence frame must be this close

  void Check() const {
    if (!(margin_m > 0) || margin_m > 2.0) throw Error("ghost measure: margin must be in (0, 2] m");
    if (frame_step < 1) throw Error("ghost measure: frame step must be >= 1");
    if (persistent_frames < 1) throw Error("ghost measure: persistent frames must be >= 1");
    if (!(max_pose_dt > 0)) throw Error("ghost measure: max pose dt must be positive");
  }
};

struct GhostStats {
  std::size_t points = 0;            // points measured
  std::size_t frames = 0;            // frames measured
  std::size_t projections = 0;       // projections onto a pixel with valid depth
  std::size_t seen_through = 0;      // of which the frame saw beyond the point by more than the margin
  std::size_t persistent_ghosts = 0; // points seen through by >= persistent_frames frames
  double fraction() const { return projections > 0 ? static_cast<double>(seen_through) / projections : 0.0; }
  // Depth consistency by range: for projections within the margin, the mean of (measured depth -
  // point depth) in bins of kRangeBin metres of measured depth (bin b = [b, b+1) * kRangeBin), a
  // figure of the sensor's depth bias at range against the map (built mostly from nearer views).
  static constexpr double kRangeBin = 0.5;
  std::vector<double> residual_sum_by_range;
  std::vector<std::size_t> residual_count_by_range;
};

class GhostMeasure {
 public:
  // points_world: the map (world frame, metres).
  GhostMeasure(const PinholeCamera& camera, std::vector<Eigen::Vector3f> points_world, const GhostMeasureOptions& options = {});

  // depth_m: CV_32F metres, 0 = invalid, the camera's raw (distorted) image size.
  void AddFrame(const Rigid3& world_from_cam, const cv::Mat& depth_m);

  GhostStats stats() const;
  // Per point (same order as the constructor's), the number of frames that saw through it.
  const std::vector<std::uint16_t>& seen_through_counts() const { return counts_; }
  const std::vector<Eigen::Vector3f>& points() const { return points_; }

 private:
  PinholeCamera camera_;
  GhostMeasureOptions options_;
  std::vector<Eigen::Vector3f> points_;
  std::vector<std::uint16_t> counts_;
  std::size_t frames_ = 0, projections_ = 0, seen_through_ = 0;
  std::vector<double> residual_sum_;
  std::vector<std::size_t> residual_count_;
};

// Feeds every options.frame_step-th pose of `trajectory` (with its nearest sequence frame within
// max_pose_dt; poses without one are skipped) into `measure`. Depth is read at depth_map_factor
// (units per metre). Returns the number of frames added.
std::size_t MeasureGhostsOverSequence(GhostMeasure* measure, const std::vector<StampedPose>& trajectory,
                                      const std::vector<FrameEntry>& frames, double depth_map_factor,
                                      const GhostMeasureOptions& options);

// Centres of the occupied leaves of an OctoMap .bt file (world frame). Throws InputError when the
// file cannot be read.
std::vector<Eigen::Vector3f> ReadOccupiedCellCentres(const std::string& path);

}  // namespace esdslam
