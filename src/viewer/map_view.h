#pragma once
// The 3-D part of the page: trajectory, keyframes, map points (static, and keypoints removed as
// dynamic), the dense map. All in the world frame (= the first keyframe's camera), metres.
// Read on the viewer thread, at most every ViewerOptions::map_interval_ms, and decimated.

#include <cstddef>
#include <deque>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dense/dense_mapper.h"
#include "dense/point_cloud.h"
#include "io/trajectory_io.h"
#include "system/frame_report.h"
#include "system/slam_system.h"
#include "viewer/viewer_options.h"

namespace esdslam {

struct MapView {
  std::vector<Eigen::Vector3f> trajectory;      // camera positions, in frame order
  std::vector<StampedPose> keyframes;           // world_from_cam
  std::vector<Eigen::Vector3f> static_points;   // live map points
  std::vector<Eigen::Vector3f> dynamic_points;  // keypoints removed as dynamic, back-projected
  std::vector<Eigen::Vector3f> culled_points;   // map points the geometry check culled as moved
  PointCloud dense;                             // dense map (empty without --dense)
  long keyframe_count = 0;                      // before decimation
  long map_point_count = 0;
  long trajectory_count = 0;
  bool finished = false;                        // the run has ended: final poses
};

// Keeps the newest `capacity` back-projected dynamic keypoints of the frames the viewer saw.
class DynamicPointTrail {
 public:
  explicit DynamicPointTrail(std::size_t capacity) : capacity_(capacity) {}
  // Adds the frame's keypoints flagged dynamic that have depth, at the frame's pose.
  void Add(const FrameReport& report);
  void Add(const std::vector<Eigen::Vector3f>& points);
  std::vector<Eigen::Vector3f> Points() const { return {points_.begin(), points_.end()}; }

 private:
  std::size_t capacity_;
  std::deque<Eigen::Vector3f> points_;
};

// Positions of `poses`, thinned (EvenSample) to max, the last one always included.
std::vector<Eigen::Vector3f> TrajectoryPositions(const std::vector<StampedPose>& poses, std::size_t max);
// The system's map now (takes Map::update_mutex through SlamSystem, then per-point locks),
// without the dense cloud. Thread-safe against tracking, local mapping and loop closing.
MapView ReadMapView(SlamSystem& system, const ViewerOptions& options);
// Thins the clouds and lists to the options' maxima.
void DecimateMapView(const ViewerOptions& options, MapView* view);
// The map event's JSON (one line); positions in mm-rounded metres.
std::string EncodeMapEvent(const MapView& view);

}  // namespace esdslam
