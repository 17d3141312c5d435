#include "viewer/frame_view.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "map/feature_set.h"
#include "system/frame_columns.h"
#include "viewer/viewer_json.h"

namespace esdslam {
namespace {

// Blends `tint` (BGR) into `picture` at half strength where `mask` (any size, CV_8U) is set.
void Tint(const cv::Mat& mask, const cv::Scalar& tint, cv::Mat* picture) {
  if (mask.empty()) return;
  cv::Mat small;
  cv::resize(mask, small, picture->size(), 0, 0, cv::INTER_NEAREST);
  cv::Mat colour(picture->size(), picture->type(), tint);
  cv::Mat blended;
  cv::addWeighted(*picture, 0.5, colour, 0.5, 0, blended);
  blended.copyTo(*picture, small);
}

void AppendPose(const TrackOutcome& track, JsonText* json) {
  json->Bool("has_pose", track.has_pose);
  if (!track.has_pose) return;
  const Vec3& t = track.world_from_cam.translation();
  const Quat& q = track.world_from_cam.rotation();
  json->BeginArray("pose");  // world_from_cam: tx ty tz qx qy qz qw (m, unit quaternion)
  for (const double v : {t.x(), t.y(), t.z()}) json->Element(v, 4);
  for (const double v : {q.x(), q.y(), q.z(), q.w()}) json->Element(v, 5);
  json->EndArray();
}

void AppendPicture(const FrameReport& report, const ViewerOptions& options, JsonText* json) {
  if (report.bgr.empty()) return;
  const cv::Mat picture = ViewerPicture(report, options.image_scale);
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", picture, jpeg, {cv::IMWRITE_JPEG_QUALITY, options.jpeg_quality});
  json->Integer("image_width", picture.cols).Integer("image_height", picture.rows);
  json->String("jpeg", Base64(jpeg));
  if (!report.features) return;
  json->BeginArray("keypoints");  // flat u, v, kind triples (px in the picture)
  for (const ViewerKeypoint& k : ViewerKeypoints(*report.features, options.image_scale, options.max_keypoints)) {
    json->Element(k.u, 1).Element(k.v, 1).Element(static_cast<int>(k.kind), 0);
  }
  json->EndArray();
}

}  // namespace

cv::Mat ViewerPicture(const FrameReport& report, double scale) {
  cv::Mat picture;
  if (report.bgr.empty()) return picture;
  cv::resize(report.bgr, picture, cv::Size(), scale, scale, cv::INTER_AREA);
  if (picture.channels() == 1) cv::cvtColor(picture, picture, cv::COLOR_GRAY2BGR);
  Tint(report.mask.mask, cv::Scalar(255, 255, 0), &picture);   // semantic: cyan
  Tint(report.geometry_mask(), cv::Scalar(255, 0, 255), &picture);  // geometry: magenta
  return picture;
}

std::vector<ViewerKeypoint> ViewerKeypoints(const FeatureSet& features, double scale, int max_keypoints) {
  std::vector<ViewerKeypoint> keypoints;
  const std::vector<std::size_t> picked = EvenSample(features.keypoints.size(), static_cast<std::size_t>(max_keypoints));
  keypoints.reserve(picked.size());
  for (const std::size_t i : picked) {
    ViewerKeypoint k;
    k.u = static_cast<float>(features.keypoints[i].pt.x * scale);
    k.v = static_cast<float>(features.keypoints[i].pt.y * scale);
    const std::uint8_t flag = i < features.is_dynamic.size() ? features.is_dynamic[i] : 0;
    k.kind = (flag & kDynamicByGeometry) != 0 ? KeypointKind::kGeometry
             : flag != 0                      ? KeypointKind::kSemantic
                                              : KeypointKind::kKept;
    keypoints.push_back(k);
  }
  return keypoints;
}

void AppendColumnValues(const std::vector<double>& values, JsonText* json) {
  const std::vector<FrameColumn>& columns = FrameColumns();
  json->Key("stages").BeginObject();  // every column in ms, by its timing.csv name
  for (std::size_t i = 0; i < columns.size() && i < values.size(); ++i)
    if (std::string(columns[i].unit) == "ms") json->Number(columns[i].name, values[i], 2);
  json->EndObject();
  json->Key("columns").BeginObject();  // the other numeric columns (counts, fractions, px)
  for (std::size_t i = 0; i < columns.size() && i < values.size(); ++i)
    if (std::string(columns[i].unit) != "ms" && columns[i].text == nullptr)
      json->Number(columns[i].name, values[i], columns[i].decimals < 0 ? 0 : columns[i].decimals);
  json->EndObject();
  for (std::size_t i = 0; i < columns.size() && i < values.size(); ++i)
    if (columns[i].text != nullptr) json->String(columns[i].name, columns[i].text(values[i]));
}

std::string EncodeFrameEvent(const FrameReport& report, const RunCounters& counters, const ViewerOptions& options) {
  JsonText json;
  json.BeginObject();
  json.Integer("index", report.index).Number("timestamp", report.timestamp, 6);
  json.Integer("frames", counters.frames).Integer("dropped", counters.dropped);
  json.Integer("keyframes", counters.keyframes).Integer("map_points", counters.map_points);
  json.Number("fps", counters.fps, 1).Integer("viewer_dropped", counters.viewer_dropped);
  json.Integer("keypoints_total", report.keypoints.total).Integer("keypoints_dynamic", report.keypoints.dynamic);
  json.Integer("keypoints_geometry", report.keypoints.by_geometry);
  AppendPose(report.track, &json);
  AppendColumnValues(ReadFrameColumns(report), &json);
  AppendPicture(report, options, &json);
  json.EndObject();
  return json.Take();
}

}  // namespace esdslam
