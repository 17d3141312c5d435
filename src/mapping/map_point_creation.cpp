// New map points from pairs of keyframes (ORB-SLAM2's CreateNewMapPoints, RGB-D flavour).
#include <cmath>
#include <limits>

#include <Eigen/SVD>

#include "feature/descriptor.h"
#include "map/keyframe.h"
#include "map/map_point.h"
#include "mapping/mapping_steps.h"

namespace esdslam {
namespace {

struct View {
  KeyFrame* keyframe;
  const FeatureSet* features;
  Rigid3 cam_from_world;
  Vec3 center;
  std::vector<MapPoint*> points;
  std::shared_ptr<const std::vector<std::uint8_t>> late_dynamic;  // KeyFrame::late_dynamic()
};

View MakeView(KeyFrame* keyframe) {
  return {keyframe, &keyframe->features(), keyframe->cam_from_world(), keyframe->camera_center(),
          keyframe->map_points(), keyframe->late_dynamic()};
}

bool Usable(const View& view, int i) {
  return view.points[i] == nullptr && !IsDynamicKeypoint(*view.features, view.late_dynamic.get(), i);
}

// Reprojection test at the 95% chi2 level (3 DoF with depth, 2 without).
bool ReprojectsWell(const View& view, int i, const Vec3& position_world) {
  const Vec3 p = view.cam_from_world * position_world;
  if (p.z() <= 0) return false;
  const RgbdRig& rig = *view.features->rig;
  const Vec2 pixel = rig.camera.Project(p);
  const double sigma2 = rig.pyramid.level_sigma2[view.features->level(i)];
  double chi2 = (pixel - view.features->pixel(i)).squaredNorm();
  if (view.features->right_u[i] >= 0) {
    const double right_error = pixel.x() - rig.bf / p.z() - view.features->right_u[i];
    return chi2 + right_error * right_error <= 7.815 * sigma2;
  }
  return chi2 <= 5.991 * sigma2;
}

Vec3 TriangulateDlt(const View& a, int i, const View& b, int j) {
  const PinholeCamera& camera = a.features->rig->camera;
  Eigen::Matrix4d design;
  const auto add_rows = [&](const View& view, int index, int row) {
    const Vec2 pixel = view.features->pixel(index);
    const double x = (pixel.x() - camera.cx()) / camera.fx(), y = (pixel.y() - camera.cy()) / camera.fy();
    Eigen::Matrix<double, 3, 4> projection = view.cam_from_world.matrix().topRows<3>();
    design.row(row) = x * projection.row(2) - projection.row(0);
    design.row(row + 1) = y * projection.row(2) - projection.row(1);
  };
  add_rows(a, i, 0);
  add_rows(b, j, 2);
  const Eigen::Vector4d h = Eigen::JacobiSVD<Eigen::Matrix4d>(design, Eigen::ComputeFullV).matrixV().col(3);
  if (std::abs(h(3)) < 1e-12) return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  return h.head<3>() / h(3);
}

// Candidate keypoint in b for keypoint i of a: by projecting its depth point, or along the epipolar
// line when it has no depth. Returns -1 when none is close enough in descriptor space.
int FindPartner(const View& a, int i, const View& b, const std::vector<bool>& taken, const Mat3& fundamental_ba) {
  const FeatureSet& fa = *a.features;
  const FeatureSet& fb = *b.features;
  const auto& pyramid = fa.rig->pyramid;
  const int level = fa.level(i);
  std::vector<int> candidates;
  if (fa.has_depth(i)) {
    const Vec3 p = b.cam_from_world * (a.cam_from_world.inverse() * fa.BackprojectCam(i));
    if (p.z() <= 0) return -1;
    const Vec2 pixel = fa.rig->camera.Project(p);
    candidates = fb.grid->FeaturesInArea(pixel.x(), pixel.y(), 8.0 * pyramid.scale_factors[level], level - 1, level + 1);
  } else {
    candidates.resize(fb.size());
    for (int j = 0; j < fb.size(); ++j) candidates[j] = j;
  }
  const Eigen::Vector3d line = fundamental_ba * Eigen::Vector3d(fa.undistorted[i].x, fa.undistorted[i].y, 1.0);
  const double line_norm = std::max(1e-12, line.head<2>().norm());
  int best = -1, best_distance = kDescriptorDistanceLow + 1;
  for (int j : candidates) {
    if (taken[j] || !Usable(b, j)) continue;
    const double epipolar = std::abs(line.dot(Eigen::Vector3d(fb.undistorted[j].x, fb.undistorted[j].y, 1.0))) / line_norm;
    if (epipolar * epipolar > 3.84 * pyramid.level_sigma2[fb.level(j)]) continue;
    const int distance = DescriptorDistance(fa.descriptor(i), fb.descriptor(j));
    if (distance < best_distance) best_distance = distance, best = j;
  }
  return best;
}

Mat3 FundamentalBFromA(const View& a, const View& b) {
  const Rigid3 b_from_a = b.cam_from_world * a.cam_from_world.inverse();
  const PinholeCamera& camera = a.features->rig->camera;
  Mat3 k_inv;
  k_inv << 1 / camera.fx(), 0, -camera.cx() / camera.fx(), 0, 1 / camera.fy(), -camera.cy() / camera.fy(), 0, 0, 1;
  const Mat3 essential = Skew(b_from_a.translation()) * b_from_a.rotation_matrix();
  return k_inv.transpose() * essential * k_inv;
}

// 3-D point for a match, or NaN when it fails the parallax/geometry checks.
Vec3 PointForMatch(const View& a, int i, const View& b, int j) {
  const FeatureSet& fa = *a.features;
  const FeatureSet& fb = *b.features;
  const RgbdRig& rig = *fa.rig;
  const double baseline = rig.bf / rig.camera.fx();
  const Vec3 ray_a = a.cam_from_world.rotation().conjugate() * rig.camera.Backproject(fa.pixel(i), 1.0);
  const Vec3 ray_b = b.cam_from_world.rotation().conjugate() * rig.camera.Backproject(fb.pixel(j), 1.0);
  const double cos_rays = ray_a.dot(ray_b) / (ray_a.norm() * ray_b.norm());
  const double cos_stereo_a = fa.has_depth(i) ? std::cos(2 * std::atan2(baseline / 2, fa.depth[i])) : 2.0;
  const double cos_stereo_b = fb.has_depth(j) ? std::cos(2 * std::atan2(baseline / 2, fb.depth[j])) : 2.0;
  const double cos_stereo = std::min(cos_stereo_a, cos_stereo_b);
  Vec3 position;
  if (cos_rays < cos_stereo && cos_rays > 0 && (fa.has_depth(i) || fb.has_depth(j) || cos_rays < 0.9998)) {
    position = TriangulateDlt(a, i, b, j);
  } else if (fa.has_depth(i) && cos_stereo_a <= cos_stereo_b) {
    position = a.cam_from_world.inverse() * fa.BackprojectCam(i);
  } else if (fb.has_depth(j) && cos_stereo_b < cos_stereo_a) {
    position = b.cam_from_world.inverse() * fb.BackprojectCam(j);
  } else {
    return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  if (!position.allFinite() || !ReprojectsWell(a, i, position) || !ReprojectsWell(b, j, position))
    return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  const double distance_a = (position - a.center).norm(), distance_b = (position - b.center).norm();
  if (distance_a <= 0 || distance_b <= 0) return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  const double ratio_distance = distance_b / distance_a;
  const double ratio_octave = rig.pyramid.scale_factors[fa.level(i)] / rig.pyramid.scale_factors[fb.level(j)];
  const double ratio_factor = 1.5 * rig.pyramid.scale_factor;
  if (ratio_distance * ratio_factor < ratio_octave || ratio_distance > ratio_octave * ratio_factor)
    return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  return position;
}

MapPoint* CreatePoint(Map* map, View* a, int i, View* b, int j, const Vec3& position) {
  MapPoint* point = map->CreateMapPoint(position, a->keyframe);
  point->AddObservation(a->keyframe, i, a->features->has_depth(i));
  point->AddObservation(b->keyframe, j, b->features->has_depth(j));
  a->keyframe->AddMapPoint(point, i);
  b->keyframe->AddMapPoint(point, j);
  a->points[i] = point;
  b->points[j] = point;
  point->ComputeDistinctiveDescriptor();
  point->UpdateNormalAndDepth();
  map->AddMapPoint(point);
  return point;
}

}  // namespace

int CreateMapPointsFromNeighbours(Map* map, KeyFrame* keyframe, int num_neighbours,
                                  std::vector<MapPoint*>* recent_points) {
  View current = MakeView(keyframe);
  const RgbdRig& rig = keyframe->rig();
  const double baseline = rig.bf / rig.camera.fx();
  int created = 0;
  for (KeyFrame* neighbour_keyframe : keyframe->BestCovisibleKeyframes(num_neighbours)) {
    if (neighbour_keyframe->is_bad()) continue;
    View neighbour = MakeView(neighbour_keyframe);
    if ((neighbour.center - current.center).norm() < baseline) continue;
    const Mat3 fundamental = FundamentalBFromA(current, neighbour);
    std::vector<bool> taken(neighbour.features->size(), false);
    for (int i = 0; i < current.features->size(); ++i) {
      if (!Usable(current, i)) continue;
      const int j = FindPartner(current, i, neighbour, taken, fundamental);
      if (j < 0) continue;
      const Vec3 position = PointForMatch(current, i, neighbour, j);
      if (!position.allFinite()) continue;
      taken[j] = true;
      recent_points->push_back(CreatePoint(map, &current, i, &neighbour, j, position));
      ++created;
    }
  }
  return created;
}

}  // namespace esdslam
