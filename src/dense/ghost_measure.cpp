#include "dense/ghost_measure.h"

#include <algorithm>
#include <cmath>
#include <limits>

#ifdef ESDSLAM_HAVE_OCTOMAP
#include <octomap/OcTree.h>
#endif

namespace esdslam {

GhostMeasure::GhostMeasure(const PinholeCamera& camera, std::vector<Eigen::Vector3f> points_world, const GhostMeasureOptions& options)
    : camera_(camera), options_(options), points_(std::move(points_world)), counts_(points_.size(), 0) {
  options_.Check();
}

void GhostMeasure::AddFrame(const Rigid3& world_from_cam, const cv::Mat& depth_m) {
  if (depth_m.type() != CV_32F || depth_m.cols != camera_.width() || depth_m.rows != camera_.height())
    throw Error("ghost measure: depth must be CV_32F of the camera's image size");
  const Rigid3 cam_from_world = world_from_cam.inverse();
  const Eigen::Matrix3f rotation = cam_from_world.rotation_matrix().cast<float>();
  const Eigen::Vector3f translation = cam_from_world.translation().cast<float>();
  const bool distorted = camera_.intrinsics().HasDistortion();
  const float margin = static_cast<float>(options_.margin_m);
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3f p = rotation * points_[i] + translation;
    if (!(p.z() > 0.05f)) continue;
    Vec2 pixel = camera_.Project(p.cast<double>());
    if (distorted) pixel = camera_.Distort(pixel);
    const long u = std::lround(pixel.x()), v = std::lround(pixel.y());
    if (u < 0 || v < 0 || u >= depth_m.cols || v >= depth_m.rows) continue;
    const float measured = depth_m.at<float>(static_cast<int>(v), static_cast<int>(u));
    if (!std::isfinite(measured) || !(measured > 0)) continue;
    ++projections_;
    if (std::abs(measured - p.z()) <= margin) {
      const auto bin = static_cast<std::size_t>(measured / GhostStats::kRangeBin);
      if (bin >= residual_sum_.size()) {
        residual_sum_.resize(bin + 1, 0.0);
        residual_count_.resize(bin + 1, 0);
      }
      residual_sum_[bin] += measured - p.z();
      ++residual_count_[bin];
    }
    if (measured > p.z() + margin) {
      ++seen_through_;
      if (counts_[i] < std::numeric_limits<std::uint16_t>::max()) ++counts_[i];
    }
  }
  ++frames_;
}

GhostStats GhostMeasure::stats() const {
  GhostStats stats;
  stats.points = points_.size();
  stats.frames = frames_;
  stats.projections = projections_;
  stats.seen_through = seen_through_;
  stats.residual_sum_by_range = residual_sum_;
  stats.residual_count_by_range = residual_count_;
  stats.persistent_ghosts = static_cast<std::size_t>(std::count_if(
      counts_.begin(), counts_.end(), [&](std::uint16_t n) { return n >= options_.persistent_frames; }));
  return stats;
}

std::size_t MeasureGhostsOverSequence(GhostMeasure* measure, const std::vector<StampedPose>& trajectory,
                                      const std::vector<FrameEntry>& frames, double depth_map_factor,
                                      const GhostMeasureOptions& options) {
  std::size_t added = 0;
  for (std::size_t i = 0; i < trajectory.size(); i += static_cast<std::size_t>(options.frame_step)) {
    const FrameEntry* frame = NearestFrame(frames, trajectory[i].timestamp, options.max_pose_dt);
    if (frame == nullptr) continue;
    measure->AddFrame(trajectory[i].world_from_cam, LoadRgbd(*frame, depth_map_factor).depth_m);
    ++added;
  }
  return added;
}

std::vector<Eigen::Vector3f> ReadOccupiedCellCentres(const std::string& path) {
#ifdef ESDSLAM_HAVE_OCTOMAP
  octomap::OcTree tree(0.1);
  if (!tree.readBinary(path)) throw InputError(path, 0, "cannot read the OctoMap file (binary .bt expected)");
  std::vector<Eigen::Vector3f> centres;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    // A leaf may be a pruned inner node covering several cells: take every cell's centre.
    const double size = it.getSize(), resolution = tree.getResolution();
    const int cells = std::max(1, static_cast<int>(std::lround(size / resolution)));
    const octomap::point3d corner = it.getCoordinate() - octomap::point3d(0.5 * size, 0.5 * size, 0.5 * size);
    for (int x = 0; x < cells; ++x)
      for (int y = 0; y < cells; ++y)
        for (int z = 0; z < cells; ++z)
          centres.emplace_back(static_cast<float>(corner.x() + (x + 0.5) * resolution), static_cast<float>(corner.y() + (y + 0.5) * resolution),
                               static_cast<float>(corner.z() + (z + 0.5) * resolution));
  }
  return centres;
#else
  throw InputError(path, 0, "this build has no OctoMap");
#endif
}

}  // namespace esdslam
