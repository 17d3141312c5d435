#include "viewer/run_replay.h"

#include <cmath>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "dense/cloud_io.h"
#include "system/frame_columns.h"
#include "viewer/map_view.h"
#include "viewer/viewer_json.h"

namespace esdslam {
namespace {

// The last row of timing.csv as column values in FrameColumns() order (NaN where absent) and
// the state text.
void AppendLastRow(const TimingTable& timing, JsonText* json) {
  const std::vector<FrameColumn>& columns = FrameColumns();
  if (timing.rows.empty()) return;
  json->Key("stages").BeginObject();
  for (const FrameColumn& column : columns)
    if (std::string(column.unit) == "ms" && timing.Has(column.name))
      json->Number(column.name, timing.Numbers(column.name).back(), 2);
  json->EndObject();
  json->Key("columns").BeginObject();
  for (const FrameColumn& column : columns)
    if (std::string(column.unit) != "ms" && column.text == nullptr && timing.Has(column.name))
      json->Number(column.name, timing.Numbers(column.name).back(), column.decimals < 0 ? 0 : column.decimals);
  json->EndObject();
  for (const FrameColumn& column : columns)
    if (column.text != nullptr && timing.Has(column.name)) json->String(column.name, timing.Text(column.name).back());
}

void AppendDebugPicture(const RunFiles& files, const ViewerOptions& options, JsonText* json) {
  if (files.debug_pictures.empty()) return;
  const cv::Mat full = cv::imread(files.debug_pictures.back().path, cv::IMREAD_COLOR);
  if (full.empty()) return;
  cv::Mat picture;
  cv::resize(full, picture, cv::Size(), options.image_scale, options.image_scale, cv::INTER_AREA);
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", picture, jpeg, {cv::IMWRITE_JPEG_QUALITY, options.jpeg_quality});
  json->Integer("image_width", picture.cols).Integer("image_height", picture.rows);
  json->String("jpeg", Base64(jpeg));
}

void AppendTimelineRows(const TimingTable& timing, const std::vector<std::size_t>& rows, JsonText* json) {
  json->BeginArray("rows");
  for (const std::size_t r : rows) json->Element(static_cast<double>(r), 0);
  json->EndArray();
  if (timing.Has("timestamp")) {
    const std::vector<double> t = timing.Numbers("timestamp");
    json->BeginArray("timestamps");
    for (const std::size_t r : rows) json->Element(t[r], 6);
    json->EndArray();
  }
  json->Key("text").BeginObject();  // text columns (state), by name
  for (const FrameColumn& column : FrameColumns()) {
    if (column.text == nullptr || !timing.Has(column.name)) continue;
    const std::vector<std::string> text = timing.Text(column.name);
    json->BeginArray(column.name);
    for (const std::size_t r : rows) json->String(nullptr, text[r]);
    json->EndArray();
  }
  json->EndObject();
  json->Key("stages").BeginObject();  // the columns in ms, by name
  for (const FrameColumn& column : FrameColumns()) {
    if (std::string(column.unit) != "ms" || !timing.Has(column.name)) continue;
    const std::vector<double> values = timing.Numbers(column.name);
    json->BeginArray(column.name);
    for (const std::size_t r : rows) json->Element(values[r], 2);
    json->EndArray();
  }
  json->EndObject();
}

}  // namespace

std::string EncodeReplayTimeline(const RunFiles& files, const ViewerOptions& options) {
  const std::size_t max = static_cast<std::size_t>(options.max_trajectory);
  JsonText json;
  json.BeginObject();
  AppendTimelineRows(files.timing, EvenSample(files.timing.rows.size(), max), &json);
  std::vector<std::size_t> poses = EvenSample(files.trajectory.size(), max);
  if (!poses.empty()) poses.back() = files.trajectory.size() - 1;
  json.BeginArray("pose_times");
  for (const std::size_t i : poses) json.Element(files.trajectory[i].timestamp, 6);
  json.EndArray();
  json.BeginArray("positions");  // flat x, y, z (m)
  for (const std::size_t i : poses) {
    const Vec3& p = files.trajectory[i].world_from_cam.translation();
    json.Element(p.x()).Element(p.y()).Element(p.z());
  }
  json.EndArray();
  json.EndObject();
  return json.Take();
}

std::string EncodeReplayFrame(const RunFiles& files, const ViewerOptions& options) {
  const long frames = static_cast<long>(files.timing.rows.size());
  long dropped = 0;
  if (files.timing.Has("dropped_before"))
    for (const double d : files.timing.Numbers("dropped_before")) dropped += std::isfinite(d) ? static_cast<long>(d) : 0;
  JsonText json;
  json.BeginObject().Bool("replay", true);
  json.Integer("index", frames - 1).Integer("frames", frames).Integer("dropped", dropped);
  json.Integer("keyframes", static_cast<long long>(files.keyframes.size()));
  json.Integer("poses", static_cast<long long>(files.trajectory.size()));
  if (!files.trajectory.empty()) json.Number("timestamp", files.trajectory.back().timestamp, 6);
  AppendLastRow(files.timing, &json);
  AppendDebugPicture(files, options, &json);
  json.EndObject();
  return json.Take();
}

RunFiles PublishRun(const ReplayInputs& inputs, const ViewerOptions& options, EventHub* hub) {
  RunFiles files = ReadRunFiles(inputs.out_dir, inputs.debug_dir);
  MapView view;
  view.trajectory_count = static_cast<long>(files.trajectory.size());
  view.trajectory = TrajectoryPositions(files.trajectory, static_cast<std::size_t>(options.max_trajectory));
  view.keyframes = files.keyframes;
  view.keyframe_count = static_cast<long>(files.keyframes.size());
  view.map_point_count = -1;  // a run writes no map points outside --save-map's binary file
  const std::string dense_ply = (std::filesystem::path(inputs.out_dir) / "dense.ply").string();
  if (std::filesystem::exists(dense_ply)) view.dense = ReadPly(dense_ply);
  view.finished = true;
  DecimateMapView(options, &view);
  hub->Publish("frame", EncodeReplayFrame(files, options));
  hub->Publish("map", EncodeMapEvent(view));
  hub->Publish("timeline", EncodeReplayTimeline(files, options));
  JsonText status;
  status.BeginObject().Bool("finished", true).Bool("replay", true).Integer("frames", static_cast<long long>(files.timing.rows.size())).EndObject();
  hub->Publish("status", status.Take());
  return files;
}

}  // namespace esdslam
