#include "tracking/frame.h"

#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "map/map_point.h"

namespace esdslam {

std::shared_ptr<const RgbdRig> MakeRgbdRig(const CameraIntrinsics& intrinsics, double bf, double th_depth,
                                           const OrbExtractor& extractor, double readout_time_s) {
  if (!(readout_time_s >= 0.0 && readout_time_s <= 1.0)) throw Error("MakeRgbdRig: readout time must be in [0, 1] s");
  auto rig = std::make_shared<RgbdRig>();
  rig->camera = PinholeCamera(intrinsics);
  rig->bf = bf;
  rig->readout_time_s = readout_time_s;
  rig->th_depth_m = th_depth * bf / intrinsics.fx;
  ScalePyramid& pyramid = rig->pyramid;
  pyramid.num_levels = extractor.num_levels();
  pyramid.scale_factor = extractor.options().scale_factor;
  pyramid.log_scale_factor = std::log(pyramid.scale_factor);
  pyramid.scale_factors = extractor.scale_factors();
  pyramid.level_sigma2 = extractor.level_sigma2();
  pyramid.inv_level_sigma2 = extractor.inv_level_sigma2();
  return rig;
}

namespace {

cv::Mat ToGray(const cv::Mat& image, bool is_rgb) {
  if (image.type() == CV_8UC1) return image;
  cv::Mat gray;
  if (image.type() == CV_8UC3) {
    cv::cvtColor(image, gray, is_rgb ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY);
  } else if (image.type() == CV_8UC4) {
    cv::cvtColor(image, gray, is_rgb ? cv::COLOR_RGBA2GRAY : cv::COLOR_BGRA2GRAY);
  } else {
    throw Error("Frame: image must be 8-bit grey, colour or colour+alpha");
  }
  return gray;
}

// The spatial grid over the undistorted keypoints, within the camera's undistorted image bounds.
std::unique_ptr<FeatureGrid> MakeGrid(const FeatureSet& features) {
  std::vector<int> levels(static_cast<std::size_t>(features.size()));
  for (int i = 0; i < features.size(); ++i) levels[i] = features.level(i);
  const PinholeCamera& camera = features.rig->camera;
  return std::make_unique<FeatureGrid>(features.undistorted, levels, camera.min_u(), camera.max_u(), camera.min_v(),
                                       camera.max_v());
}

// Depth (m) at the rounded raw keypoint position; 0 when invalid or outside.
float DepthAt(const cv::Mat& depth_m, const cv::KeyPoint& keypoint) {
  const int u = cvRound(keypoint.pt.x), v = cvRound(keypoint.pt.y);
  if (u < 0 || v < 0 || u >= depth_m.cols || v >= depth_m.rows) return 0.f;
  const float d = depth_m.at<float>(v, u);
  return std::isfinite(d) && d > 0 ? d : 0.f;
}

// The extractor maps a level-l corner to level 0 as x * s_l; with cv::resize's pixel-centre
// alignment the same image point is at (x + 0.5) * s_l - 0.5, i.e. 0.5 * (s_l - 1) px further
// right/down. Without this, keypoints of coarse levels are biased by up to ~1.3 px.
void CorrectPyramidOffsets(const std::vector<double>& scale_factors, std::vector<cv::KeyPoint>* keypoints) {
  for (cv::KeyPoint& keypoint : *keypoints) {
    const float offset = static_cast<float>(0.5 * (scale_factors[keypoint.octave] - 1.0));
    keypoint.pt.x += offset;
    keypoint.pt.y += offset;
  }
}

}  // namespace

Frame::Frame(long id, double timestamp, const cv::Mat& image, const cv::Mat& depth_m, const cv::Mat& dynamic_mask,
             const OrbExtractor& extractor, std::shared_ptr<const RgbdRig> rig, const FrameOptions& options)
    : id_(id), timestamp_(timestamp), depth_m_(depth_m), dynamic_mask_(dynamic_mask) {
  if (image.empty() || depth_m.empty()) throw Error("Frame: empty colour or depth image");
  if (depth_m.type() != CV_32FC1 || depth_m.size() != image.size())
    throw Error("Frame: depth must be CV_32F metres with the size of the colour image");
  const bool has_mask = !dynamic_mask.empty();
  if (has_mask && (dynamic_mask.type() != CV_8UC1 || dynamic_mask.size() != image.size()))
    throw Error("Frame: dynamic mask must be CV_8U with the size of the colour image");

  auto features = std::make_shared<FeatureSet>();
  features->rig = std::move(rig);
  cv::Mat extraction_mask;
  if (has_mask && options.mask_extraction) extraction_mask = dynamic_mask == 0;
  extractor.Extract(ToGray(image, options.image_is_rgb), extraction_mask, &features->keypoints, &features->descriptors);

  if (options.pyramid_centre_correction) CorrectPyramidOffsets(extractor.scale_factors(), &features->keypoints);
  const int n = features->size();
  std::vector<cv::Point2f> raw(n);
  for (int i = 0; i < n; ++i) raw[i] = features->keypoints[i].pt;
  const PinholeCamera& camera = features->rig->camera;
  features->undistorted = camera.Undistort(raw);
  features->depth.assign(n, 0.f);
  features->right_u.assign(n, -1.f);
  features->is_dynamic.assign(n, 0);
  for (int i = 0; i < n; ++i) {
    const cv::KeyPoint& keypoint = features->keypoints[i];
    const float depth = DepthAt(depth_m, keypoint);
    if (depth > 0) {
      features->depth[i] = depth;
      features->right_u[i] = static_cast<float>(features->undistorted[i].x - features->rig->bf / depth);
    }
    if (has_mask) features->is_dynamic[i] = KeypointOnMask(keypoint, dynamic_mask) ? kDynamicByMask : 0;
  }
  features->grid = MakeGrid(*features);
  features_ = std::move(features);
  map_points.assign(n, nullptr);
  outlier.assign(n, false);
}

std::optional<PointProjection> Frame::ProjectInFrustum(MapPoint* point, double min_view_cos) const {
  const Vec3 position_world = point->position();
  const Vec3 position_cam = cam_from_world * position_world;
  if (position_cam.z() <= 0) return std::nullopt;
  const PinholeCamera& camera = rig().camera;
  const Vec2 pixel = camera.Project(position_cam);
  if (!camera.InImage(pixel)) return std::nullopt;
  const Vec3 ray = position_world - camera_center();
  const double distance = ray.norm();
  if (distance < point->min_distance() || distance > point->max_distance()) return std::nullopt;
  const double view_cos = ray.dot(point->normal()) / distance;
  if (view_cos < min_view_cos) return std::nullopt;
  PointProjection projection;
  projection.point = point;
  projection.u = pixel.x();
  projection.v = pixel.y();
  projection.right_u = pixel.x() - rig().bf / position_cam.z();
  projection.predicted_level = point->PredictLevel(distance, rig().pyramid.num_levels, rig().pyramid.log_scale_factor);
  projection.view_cos = view_cos;
  return projection;
}

void Frame::DropBadAssociations() {
  for (MapPoint*& point : map_points)
    if (point != nullptr && point->is_bad()) point = nullptr;
}

void Frame::MarkDynamic(int i, std::uint8_t reason) {
  if (features_.use_count() != 1) throw Error("Frame::MarkDynamic: the features are already shared with a keyframe");
  if (i < 0 || i >= size() || reason == 0) throw Error("Frame::MarkDynamic: bad keypoint index or reason");
  features_->is_dynamic[i] = reason;
  map_points[i] = nullptr;
  outlier[i] = false;
}

void Frame::CompensateRollingShutter(const Vec3& angular_velocity_cam) {
  const RgbdRig& rig = *features_->rig;
  if (rig.readout_time_s <= 0.0) return;
  if (features_.use_count() != 1)
    throw Error("Frame::CompensateRollingShutter: the features are already shared with a keyframe");
  if (extracted_undistorted_.empty()) extracted_undistorted_ = features_->undistorted, extracted_depth_ = features_->depth;
  const PinholeCamera& camera = rig.camera;
  for (int i = 0; i < size(); ++i) {
    // Seen at row time tau, the point's direction is exp([w]x tau) times its middle-row direction.
    const double tau_s = RowTimeOffset(features_->keypoints[i].pt.y, camera.height(), rig.readout_time_s);
    const Mat3 middle_from_row = ExpSO3(-tau_s * angular_velocity_cam);
    const cv::Point2f& seen = extracted_undistorted_[i];
    const Vec3 ray = middle_from_row * Vec3((seen.x - camera.cx()) / camera.fx(), (seen.y - camera.cy()) / camera.fy(), 1.0);
    cv::Point2f& corrected = features_->undistorted[i];
    float& depth_m = features_->depth[i];
    corrected = seen;
    depth_m = extracted_depth_[i];
    if (ray.z() > 0) {  // else turned out of view (about 90 deg within the readout): left as seen
      corrected = cv::Point2f(static_cast<float>(camera.fx() * ray.x() / ray.z() + camera.cx()),
                              static_cast<float>(camera.fy() * ray.y() / ray.z() + camera.cy()));
      // The depth reading is z at the row's time (the seen ray has z = 1): z of the turned ray.
      depth_m = static_cast<float>(depth_m * ray.z());
    }
    if (depth_m > 0) features_->right_u[i] = static_cast<float>(corrected.x - rig.bf / depth_m);
  }
  features_->grid = MakeGrid(*features_);
}

int Frame::NumWithDepth() const {
  int count = 0;
  for (float d : features().depth) count += d > 0;
  return count;
}

}  // namespace esdslam
