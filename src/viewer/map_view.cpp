#include "viewer/map_view.h"

#include "map/map.h"
#include "viewer/viewer_json.h"

namespace esdslam {
namespace {

template <typename T>
std::vector<T> Thinned(const std::vector<T>& items, std::size_t max) {
  if (items.size() <= max) return items;
  std::vector<T> kept;
  kept.reserve(max);
  for (const std::size_t i : EvenSample(items.size(), max)) kept.push_back(items[i]);
  return kept;
}

void AppendPoints(const char* key, const std::vector<Eigen::Vector3f>& points, JsonText* json) {
  json->BeginArray(key);  // flat x, y, z (m)
  for (const Eigen::Vector3f& p : points) json->Element(p.x()).Element(p.y()).Element(p.z());
  json->EndArray();
}

void AppendKeyframes(const std::vector<StampedPose>& keyframes, JsonText* json) {
  json->BeginArray("keyframes");  // flat tx ty tz qx qy qz qw (world_from_cam)
  for (const StampedPose& pose : keyframes) {
    const Vec3& t = pose.world_from_cam.translation();
    const Quat& q = pose.world_from_cam.rotation();
    json->Element(t.x()).Element(t.y()).Element(t.z());
    json->Element(q.x(), 4).Element(q.y(), 4).Element(q.z(), 4).Element(q.w(), 4);
  }
  json->EndArray();
}

}  // namespace

void DynamicPointTrail::Add(const FrameReport& report) {
  if (!report.track.has_pose || !report.features || capacity_ == 0) return;
  const FeatureSet& features = *report.features;
  for (int i = 0; i < features.size(); ++i) {
    if (features.is_dynamic[i] == 0 || !features.has_depth(i)) continue;
    const Vec3 world = report.track.world_from_cam * features.BackprojectCam(i);
    points_.push_back(world.cast<float>());
    if (points_.size() > capacity_) points_.pop_front();
  }
}

void DynamicPointTrail::Add(const std::vector<Eigen::Vector3f>& points) {
  for (const Eigen::Vector3f& p : points) {
    points_.push_back(p);
    if (points_.size() > capacity_) points_.pop_front();
  }
}

std::vector<Eigen::Vector3f> TrajectoryPositions(const std::vector<StampedPose>& poses, std::size_t max) {
  std::vector<Eigen::Vector3f> positions;
  std::vector<std::size_t> picked = EvenSample(poses.size(), max);
  if (!picked.empty() && picked.back() != poses.size() - 1) picked.back() = poses.size() - 1;
  positions.reserve(picked.size());
  for (const std::size_t i : picked) positions.push_back(poses[i].world_from_cam.translation().cast<float>());
  return positions;
}

MapView ReadMapView(SlamSystem& system, const ViewerOptions& options) {
  MapView view;
  const std::vector<StampedPose> trajectory = system.Trajectory();
  view.trajectory_count = static_cast<long>(trajectory.size());
  view.trajectory = TrajectoryPositions(trajectory, static_cast<std::size_t>(options.max_trajectory));
  view.keyframes = system.KeyFrameTrajectory();
  view.keyframe_count = static_cast<long>(view.keyframes.size());
  const std::vector<MapPoint*> points = system.map().map_points();
  view.map_point_count = static_cast<long>(points.size());
  for (const std::size_t i : EvenSample(points.size(), static_cast<std::size_t>(options.max_map_points))) {
    if (!points[i]->is_bad()) view.static_points.push_back(points[i]->position().cast<float>());
  }
  DecimateMapView(options, &view);
  return view;
}

void DecimateMapView(const ViewerOptions& options, MapView* view) {
  view->keyframes = Thinned(view->keyframes, static_cast<std::size_t>(options.max_trajectory));
  view->static_points = Thinned(view->static_points, static_cast<std::size_t>(options.max_map_points));
  view->dynamic_points = Thinned(view->dynamic_points, static_cast<std::size_t>(options.max_dynamic_points));
  view->culled_points = Thinned(view->culled_points, static_cast<std::size_t>(options.max_dynamic_points));
  const std::size_t max_dense = static_cast<std::size_t>(options.max_dense_points);
  if (view->dense.size() > max_dense) {
    PointCloud thin;
    thin.reserve(max_dense);
    for (const std::size_t i : EvenSample(view->dense.size(), max_dense))
      thin.push_back(view->dense.points[i], view->dense.colors[i]);
    view->dense = std::move(thin);
  }
}

std::string EncodeMapEvent(const MapView& view) {
  JsonText json;
  json.BeginObject();
  json.Integer("keyframe_count", view.keyframe_count).Integer("map_point_count", view.map_point_count);
  json.Integer("trajectory_count", view.trajectory_count).Bool("finished", view.finished);
  AppendPoints("trajectory", view.trajectory, &json);
  AppendKeyframes(view.keyframes, &json);
  AppendPoints("static_points", view.static_points, &json);
  AppendPoints("dynamic_points", view.dynamic_points, &json);
  AppendPoints("culled_points", view.culled_points, &json);
  AppendPoints("dense_points", view.dense.points, &json);
  json.BeginArray("dense_colors");  // flat r, g, b (0..255)
  for (const Rgb8& c : view.dense.colors) json.Element(c.r, 0).Element(c.g, 0).Element(c.b, 0);
  json.EndArray();
  json.EndObject();
  return json.Take();
}

}  // namespace esdslam
