#include "tracking/frame_matcher.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "feature/descriptor.h"
#include "map/keyframe.h"
#include "map/map_point.h"

namespace esdslam {

std::vector<int> RotationInconsistentMatches(const std::vector<std::pair<float, int>>& angle_pairs) {
  // ORB-SLAM2 builds a 30-entry histogram but indexes it with round(rotation / 30), i.e. 30-degree
  // bins; we keep that effective bin width.
  constexpr int kBins = 12;
  std::array<std::vector<int>, kBins> histogram;
  for (const auto& [difference, id] : angle_pairs) {
    float rotation = difference;
    if (rotation < 0) rotation += 360.f;
    int bin = static_cast<int>(std::round(rotation / 30.f));
    if (bin == kBins) bin = 0;
    histogram[std::clamp(bin, 0, kBins - 1)].push_back(id);
  }
  std::array<int, 3> best{-1, -1, -1};
  std::array<std::size_t, 3> best_count{0, 0, 0};
  for (int bin = 0; bin < kBins; ++bin) {
    const std::size_t count = histogram[bin].size();
    for (int k = 0; k < 3; ++k) {
      if (count > best_count[k]) {
        for (int m = 2; m > k; --m) best[m] = best[m - 1], best_count[m] = best_count[m - 1];
        best[k] = bin, best_count[k] = count;
        break;
      }
    }
  }
  for (int k = 1; k < 3; ++k)
    if (best_count[k] < 0.1 * best_count[0]) best[k] = -1;
  std::vector<int> discard;
  for (int bin = 0; bin < kBins; ++bin) {
    if (bin == best[0] || bin == best[1] || bin == best[2]) continue;
    discard.insert(discard.end(), histogram[bin].begin(), histogram[bin].end());
  }
  return discard;
}

void ApplyMatches(const FrameMatches& matches, Frame* frame) {
  frame->map_points = matches.map_points;
  for (int j : matches.matched) frame->outlier[j] = false;
}

namespace {

// The current frame's candidate keypoints for a point seen at `last_level` in the last frame: by
// the camera's motion along its axis (RGB-D), the expected level shifts.
std::vector<int> CandidatesByMotion(const FeatureSet& features, const Vec2& pixel, double radius, int last_level,
                                    bool forward, bool backward) {
  if (forward) return features.grid->FeaturesInArea(pixel.x(), pixel.y(), radius, last_level);
  if (backward) return features.grid->FeaturesInArea(pixel.x(), pixel.y(), radius, 0, last_level);
  return features.grid->FeaturesInArea(pixel.x(), pixel.y(), radius, last_level - 1, last_level + 1);
}

// Drops the matches the rotation histogram rejects.
void DropRotationInconsistent(const std::vector<std::pair<float, int>>& angles, FrameMatches* result) {
  for (int j : RotationInconsistentMatches(angles)) {
    result->map_points[j] = nullptr;
    --result->count;
  }
}

}  // namespace

FrameMatches SearchByProjection(const Frame& current, const Frame& last, double radius_px) {
  const FeatureSet& features = current.features();
  const auto& scale_factors = features.rig->pyramid.scale_factors;
  const Rigid3& cam_from_world = current.cam_from_world;
  const Vec3 last_center_in_current = cam_from_world * last.camera_center();
  const double baseline = features.rig->bf / features.rig->camera.fx();
  const bool forward = -last_center_in_current.z() > baseline;
  const bool backward = last_center_in_current.z() > baseline;
  FrameMatches result;
  result.map_points.assign(current.size(), nullptr);
  std::vector<std::pair<float, int>> angles;
  for (int i = 0; i < last.size(); ++i) {
    MapPoint* point = last.map_points[i];
    if (point == nullptr || last.outlier[i]) continue;
    const Vec3 position_cam = cam_from_world * point->position();
    if (position_cam.z() <= 0) continue;
    const Vec2 pixel = features.rig->camera.Project(position_cam);
    if (!features.rig->camera.InImage(pixel)) continue;
    const int last_level = last.features().level(i);
    const double radius = radius_px * scale_factors[last_level];
    const std::vector<int> candidates = CandidatesByMotion(features, pixel, radius, last_level, forward, backward);
    if (candidates.empty()) continue;
    const cv::Mat descriptor = point->descriptor();
    if (descriptor.empty()) continue;
    const double right_u = pixel.x() - features.rig->bf / position_cam.z();
    int best_distance = std::numeric_limits<int>::max(), best = -1;
    for (int j : candidates) {
      if (features.is_dynamic[j]) continue;
      const MapPoint* existing = result.map_points[j];
      if (existing != nullptr && existing->num_observations() > 0) continue;
      if (features.right_u[j] > 0 && std::abs(right_u - features.right_u[j]) > radius) continue;
      const int distance = DescriptorDistance(descriptor.ptr<unsigned char>(0), features.descriptor(j));
      if (distance < best_distance) best_distance = distance, best = j;
    }
    if (best < 0 || best_distance > kDescriptorDistanceHigh) continue;
    result.map_points[best] = point;
    result.matched.push_back(best);
    angles.emplace_back(last.features().keypoints[i].angle - features.keypoints[best].angle, best);
    ++result.count;
  }
  DropRotationInconsistent(angles, &result);
  return result;
}

FrameMatches SearchLocalPoints(const Frame& frame, const std::vector<PointProjection>& projections,
                               double radius_factor) {
  const FeatureSet& features = frame.features();
  const auto& scale_factors = features.rig->pyramid.scale_factors;
  FrameMatches result;
  result.map_points = frame.map_points;
  for (const PointProjection& projection : projections) {
    MapPoint* point = projection.point;
    if (point->is_bad()) continue;
    const int level = projection.predicted_level;
    const double window = (projection.view_cos > 0.998 ? 2.5 : 4.0) * radius_factor * scale_factors[level];
    const auto nearby = features.grid->FeaturesInArea(projection.u, projection.v, window, level - 1, level);
    if (nearby.empty()) continue;
    const cv::Mat descriptor = point->descriptor();
    if (descriptor.empty()) continue;
    int best_distance = 256, second_distance = 256, best_level = -1, second_level = -1, best = -1;
    for (int j : nearby) {
      if (features.is_dynamic[j]) continue;
      const MapPoint* existing = result.map_points[j];
      if (existing != nullptr && existing->num_observations() > 0) continue;
      if (features.right_u[j] > 0 && std::abs(projection.right_u - features.right_u[j]) > window) continue;
      const int distance = DescriptorDistance(descriptor.ptr<unsigned char>(0), features.descriptor(j));
      if (distance < best_distance) {
        second_distance = best_distance, second_level = best_level;
        best_distance = distance, best_level = features.level(j), best = j;
      } else if (distance < second_distance) {
        second_distance = distance, second_level = features.level(j);
      }
    }
    if (best < 0 || best_distance > kDescriptorDistanceHigh) continue;
    if (best_level == second_level && best_distance > 0.8 * second_distance) continue;
    result.map_points[best] = point;
    result.matched.push_back(best);
    ++result.count;
  }
  return result;
}

FrameMatches SearchKeyFrameBruteForce(const KeyFrame& keyframe, const Frame& frame) {
  const FeatureSet& kf_features = keyframe.features();
  const FeatureSet& features = frame.features();
  const std::vector<MapPoint*> kf_points = keyframe.map_points();
  std::vector<int> best_for_frame(features.size(), -1), best_distance_for_frame(features.size(), 256);
  std::vector<std::pair<int, int>> proposals;  // (kf index, frame index)
  for (int i = 0; i < kf_features.size(); ++i) {
    MapPoint* point = kf_points[i];
    if (point == nullptr || point->is_bad()) continue;
    int best = -1, best_distance = 256, second_distance = 256;
    for (int j = 0; j < features.size(); ++j) {
      if (features.is_dynamic[j]) continue;
      const int distance = DescriptorDistance(kf_features.descriptor(i), features.descriptor(j));
      if (distance < best_distance) second_distance = best_distance, best_distance = distance, best = j;
      else if (distance < second_distance) second_distance = distance;
    }
    if (best < 0 || best_distance > kDescriptorDistanceLow + 10 || best_distance > 0.7 * second_distance) continue;
    if (best_distance < best_distance_for_frame[best]) {
      best_distance_for_frame[best] = best_distance;
      best_for_frame[best] = i;
    }
    proposals.emplace_back(i, best);
  }
  FrameMatches result;
  result.map_points.assign(features.size(), nullptr);
  std::vector<std::pair<float, int>> angles;
  for (const auto& [i, j] : proposals) {
    if (best_for_frame[j] != i) continue;  // mutual best only
    result.map_points[j] = kf_points[i];
    result.matched.push_back(j);
    angles.emplace_back(kf_features.keypoints[i].angle - features.keypoints[j].angle, j);
  }
  result.count = static_cast<int>(angles.size());
  DropRotationInconsistent(angles, &result);
  return result;
}

}  // namespace esdslam
