#include "dynamic/reference_keyframes.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "common/error.h"

namespace esdslam {

std::vector<int> SelectReferenceKeyframes(const std::vector<int>& shared_point_counts, int max_count) {
  if (max_count < 0) throw Error("SelectReferenceKeyframes: max_count must be >= 0");
  std::vector<int> order(shared_point_counts.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return shared_point_counts[a] > shared_point_counts[b]; });
  std::vector<int> chosen;
  for (const int k : order) {
    if (static_cast<int>(chosen.size()) >= max_count || shared_point_counts[k] <= 0) break;
    chosen.push_back(k);
  }
  return chosen;
}

std::vector<int> WithoutYoungKeyframes(std::vector<int> shared_point_counts, const std::vector<double>& keyframe_times_s,
                                       double frame_time_s, double min_age_s) {
  if (keyframe_times_s.size() != shared_point_counts.size())
    throw Error("WithoutYoungKeyframes: one keyframe time per count expected");
  const double newest_s = frame_time_s - min_age_s;
  bool any_old_enough = false;
  for (std::size_t k = 0; k < shared_point_counts.size(); ++k)
    any_old_enough |= shared_point_counts[k] > 0 && keyframe_times_s[k] <= newest_s;
  if (!any_old_enough) return shared_point_counts;
  for (std::size_t k = 0; k < shared_point_counts.size(); ++k)
    if (keyframe_times_s[k] > newest_s) shared_point_counts[k] = 0;
  return shared_point_counts;
}

std::vector<int> SelectKeyframesByViewOverlap(const PinholeCamera& camera, const Rigid3& cam_from_world,
                                              const std::vector<Rigid3>& keyframe_world_from_cams,
                                              double scene_depth_m, int max_count, double max_parallax_deg) {
  if (!(scene_depth_m > 0)) throw Error("SelectKeyframesByViewOverlap: scene_depth_m must be > 0");
  const Vec3 centre = cam_from_world.inverse().translation();
  const double min_cosine = std::cos(max_parallax_deg * M_PI / 180.0);
  std::vector<int> scores(keyframe_world_from_cams.size(), 0);
  for (std::size_t k = 0; k < keyframe_world_from_cams.size(); ++k) {
    const Rigid3& world_from_keyframe = keyframe_world_from_cams[k];
    for (int gy = 0; gy < 12; ++gy) {
      for (int gx = 0; gx < 16; ++gx) {
        const Vec2 pixel((gx + 0.5) * camera.width() / 16.0, (gy + 0.5) * camera.height() / 12.0);
        const Vec3 point = world_from_keyframe * camera.Backproject(pixel, scene_depth_m);
        const Vec3 in_cam = cam_from_world * point;
        if (in_cam.z() <= 0.05 || !camera.InImage(camera.Project(in_cam))) continue;
        const Vec3 a = (point - world_from_keyframe.translation()).normalized();
        const Vec3 b = (point - centre).normalized();
        if (a.dot(b) >= min_cosine) ++scores[k];
      }
    }
  }
  return SelectReferenceKeyframes(scores, max_count);
}

}  // namespace esdslam
