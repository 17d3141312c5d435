// esdslam::System (include/esdslam/esdslam.h): the per-frame pipeline (system/pipeline.h) behind
// the public API, with the run's growing output files when out_dir is set.
#include <atomic>
#include <mutex>
#include <filesystem>
#include <optional>

#include <fmt/format.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "api/api_config.h"
#include "common/data_files.h"
#include "common/error.h"
#include "esdslam/esdslam.h"
#include "system/frame_columns.h"
#include "system/live_outputs.h"
#include "system/pipeline.h"
#include "system/run_outputs.h"
#include "system/run_settings.h"
#include "viewer/live_viewer.h"

namespace esdslam {
namespace {

// depth_m as the pipeline takes it: CV_32F metres (a copy), from CV_32F or from CV_16U in
// DepthMapFactor units.
cv::Mat DepthMetres(const cv::Mat& depth, double depth_map_factor, double timestamp) {
  cv::Mat metres;
  if (depth.type() == CV_32FC1) metres = depth.clone();
  else if (depth.type() == CV_16UC1) depth.convertTo(metres, CV_32F, 1.0 / depth_map_factor);
  else
    throw Error(fmt::format("frame {:.6f}: depth must be CV_32FC1 metres or CV_16UC1 (DepthMapFactor units), got "
                            "OpenCV type {}",
                            timestamp, depth.type()));
  return metres;
}

KeyFrameInfo KeyFrameInfoOf(const KeyFrame& keyframe) {
  return {keyframe.id(), keyframe.timestamp(), ToMatrix4(keyframe.world_from_cam())};
}

FrameStats StatsOf(const FrameReport& report) {
  FrameStats stats;
  stats.index = report.index;
  stats.keypoints = report.keypoints.total;
  stats.dynamic_keypoints = report.keypoints.dynamic;
  stats.inliers = report.track.inliers;
  stats.mask_ms = report.mask.refine_ms + report.mask_wait_ms;
  stats.extract_ms = report.track.extract_ms;
  stats.track_ms = report.track.track_ms;
  stats.label_age = report.label_age();
  return stats;
}

// Log lines go to stderr, as the CLI's (stdout is the caller's): spdlog's stock default logger
// (stdout) is replaced once; a logger the caller installed is kept.
void LogToStderr() {
  static std::once_flag once;
  std::call_once(once, [] {
    const std::shared_ptr<spdlog::logger> current = spdlog::default_logger();
    for (const spdlog::sink_ptr& sink : current->sinks()) {
      if (dynamic_cast<spdlog::sinks::stdout_color_sink_mt*>(sink.get()) == nullptr) continue;
      auto logger = std::make_shared<spdlog::logger>("", std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
      logger->set_level(current->level());
      spdlog::set_default_logger(logger);
      return;
    }
  });
}

}  // namespace

struct System::Impl {
  explicit Impl(const SystemConfig& api_config) : config((LogToStderr(), ResolveApiConfig(api_config))) {
    const std::string& out_dir = config.run.out_dir;
    if (!out_dir.empty()) std::filesystem::create_directories(out_dir);
    LogRunConfig(config);
    pipeline = std::make_unique<Pipeline>(config);
    if (!out_dir.empty()) live.emplace(out_dir);
    if (api_config.viewer_port >= 0) {
      ViewerOptions options;
      options.port = api_config.viewer_port;
      options.address = api_config.viewer_address;
      viewer = std::make_unique<LiveViewer>(options, &pipeline->system(), pipeline->dense());
    }
  }

  TrackResult Track(RgbdFrame frame);
  void Notify(const FrameReport& report);

  const RunConfig config;
  std::unique_ptr<Pipeline> pipeline;
  std::optional<LiveOutputs> live;  // with out_dir
  std::unique_ptr<LiveViewer> viewer;  // with viewer_port >= 0; after the pipeline: closed before it
  Callbacks callbacks;
  int loops_closed = 0;
  int relocalizations = 0;
  bool shut_down = false;
};

TrackResult System::Impl::Track(RgbdFrame frame) {
  if (shut_down) throw Error("System::Track after Shutdown");
  const FrameReport report = pipeline->Track(frame);
  if (live) live->Add(report, ReadFrameColumns(report));
  if (viewer) viewer->Offer(report);  // headers only; encoded on the viewer thread
  TrackResult result;
  result.status = ToStatus(report.track.state);
  result.has_pose = report.track.has_pose;
  if (result.has_pose) result.world_from_cam = ToMatrix4(report.track.world_from_cam);
  result.new_keyframe = report.track.new_keyframe;
  result.stats = StatsOf(report);
  Notify(report);
  return result;
}

// The callbacks for what this frame changed (on the caller's thread).
void System::Impl::Notify(const FrameReport& report) {
  const SlamSystem& slam = pipeline->system();
  if (report.track.new_keyframe && report.track.keyframe != nullptr && callbacks.keyframe_added)
    callbacks.keyframe_added(KeyFrameInfoOf(*report.track.keyframe));
  const int relocalized_now = slam.relocalizations();
  if (relocalized_now > relocalizations && callbacks.relocalized && report.track.has_pose)
    callbacks.relocalized({report.timestamp, ToMatrix4(report.track.world_from_cam)});
  relocalizations = relocalized_now;
  const int loops_now = slam.loop_stats().loops_closed;
  if (loops_now > loops_closed && callbacks.loop_closed) callbacks.loop_closed(loops_now);
  loops_closed = loops_now;
}

System::System(const SystemConfig& config) : impl_(std::make_unique<Impl>(config)) {}

System::~System() = default;

TrackResult System::Track(const cv::Mat& bgr, const cv::Mat& depth_m, double timestamp, const cv::Mat& dynamic_mask,
                          const cv::Mat& labels) {
  RgbdFrame frame;
  frame.timestamp = timestamp;
  frame.bgr = bgr.clone();  // the pipeline keeps the images (dense keyframes, the mask thread)
  frame.depth_m = DepthMetres(depth_m, impl_->config.settings.core.depth_map_factor, timestamp);
  if (frame.depth_m.size() != frame.bgr.size())
    throw Error(fmt::format("frame {:.6f}: depth is {}x{}, the image {}x{}", timestamp, depth_m.cols, depth_m.rows,
                            bgr.cols, bgr.rows));
  if (!dynamic_mask.empty()) frame.dynamic_mask = dynamic_mask.clone();
  if (!labels.empty()) frame.labels = labels.clone();
  return impl_->Track(std::move(frame));
}

void System::Shutdown() {
  if (impl_->shut_down) return;
  impl_->shut_down = true;
  if (impl_->live) WriteRunResults(*impl_->pipeline, *impl_->live, impl_->config.run.out_dir);
  else impl_->pipeline->StopSlam();
  if (impl_->viewer) impl_->viewer->Finish();  // the final poses and map to the page
}

void System::SetCallbacks(Callbacks callbacks) { impl_->callbacks = std::move(callbacks); }

void System::SaveMap(const std::string& path) { impl_->pipeline->system().SaveMap(path); }

std::vector<TimedPose> System::Trajectory() const {
  std::vector<TimedPose> poses;
  for (const StampedPose& pose : impl_->pipeline->system().Trajectory())
    poses.push_back({pose.timestamp, ToMatrix4(pose.world_from_cam)});
  return poses;
}

std::vector<KeyFrameInfo> System::KeyFrames() const {
  std::vector<KeyFrameInfo> keyframes;
  for (const KeyFrame* keyframe : impl_->pipeline->system().map().keyframes())
    keyframes.push_back(KeyFrameInfoOf(*keyframe));
  return keyframes;
}

std::vector<MapPointInfo> System::MapPoints() const {
  std::vector<MapPointInfo> points;
  for (const MapPoint* point : impl_->pipeline->system().map().map_points()) {
    if (point->is_bad()) continue;
    const Vec3 p = point->position();
    points.push_back({point->id(), {p.x(), p.y(), p.z()}, point->num_observing_keyframes()});
  }
  return points;
}

std::string System::ViewerUrl() const { return impl_->viewer ? impl_->viewer->url() : std::string(); }

TrackingStatus System::status() const { return ToStatus(impl_->pipeline->system().state()); }

std::string System::EffectiveSettings() const { return RunSettingsYaml(impl_->config.settings); }

std::string DataDirectory() { return InstalledDataDir(); }

const char* Version() { return ESDSLAM_VERSION; }

}  // namespace esdslam
