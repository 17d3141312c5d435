#include "dense/dense_mapper.h"

#include <algorithm>
#include <ctime>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <spdlog/spdlog.h>

#include "common/error.h"
#include "common/timer.h"

namespace esdslam {

namespace {

double ThreadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

}  // namespace

DenseMapper::DenseMapper(const PinholeCamera& camera, const DenseOptions& options, KeyframePoseSource poses,
                         const DenseMapperOptions& mapper_options)
    : map_(camera, options),
      poses_(std::move(poses)),
      mapper_options_(mapper_options),
      worker_("dense mapping", ThreadedOrInline(mapper_options.threaded), mapper_options.queue_capacity,
              [this](const DenseKeyframe& keyframe) { Process(keyframe); }) {
  if (!mapper_options_.mask_dir.empty()) std::filesystem::create_directories(mapper_options_.mask_dir);
  worker_.Start();
}

DenseMapper::~DenseMapper() {
  try {
    Finish();
  } catch (const std::exception&) {  // logged when it happened
  }
}

void DenseMapper::AddKeyframe(DenseKeyframe keyframe) {
  const Stopwatch watch;
  const long id = keyframe.id;
  if (!worker_.Push(std::move(keyframe))) spdlog::warn("dense: keyframe {} arrived after Finish(); ignored", id);
  if (!worker_.threaded()) {
    worker_.Drain();  // integrated now, on this thread
    return;
  }
  const double ms = watch.ElapsedMs();
  std::lock_guard<std::mutex> lock(stats_mutex_);
  handoff_total_ms_ += ms;
  handoff_max_ms_ = std::max(handoff_max_ms_, ms);
  ++handoffs_;
}

void DenseMapper::Finish() { worker_.Close(); }

KeyframePoses DenseMapper::CurrentPoses() const { return map_.Resolve(poses_ ? poses_() : KeyframePoses{}); }

PointCloud DenseMapper::CurrentCloud() const { return map_.BuildGlobalCloud(CurrentPoses()); }

DenseOutputSummary DenseMapper::WriteOutputs(const std::string& dir, const DenseOutputFiles& files) const {
  return WriteDenseOutputs(map_, CurrentPoses(), dir, files);
}

DenseMapperStats DenseMapper::stats() const {
  DenseMapperStats stats;
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    stats.keyframes = processed_;
    stats.mean_keyframe_ms = processed_ > 0 ? total_ms_ / processed_ : 0.0;
    stats.max_keyframe_ms = max_ms_;
    stats.mean_pose_ms = processed_ > 0 ? pose_ms_ / processed_ : 0.0;
    stats.mean_keyframe_cpu_ms = processed_ > 0 ? cpu_ms_ / processed_ : 0.0;
    stats.mean_handoff_ms = handoffs_ > 0 ? handoff_total_ms_ / handoffs_ : 0.0;
    stats.max_handoff_ms = handoff_max_ms_;
  }
  stats.map = map_.stats();
  return stats;
}

void DenseMapper::Process(const DenseKeyframe& keyframe) {
  const Stopwatch watch;
  const double cpu_start = ThreadCpuMs();
  const KeyframePoses poses = poses_ ? poses_() : KeyframePoses{};
  const double pose_ms = watch.ElapsedMs();
  // Keyframes waiting: the dense thread is behind, so it re-indexes only keyframes that moved a voxel.
  map_.Integrate(keyframe, poses, worker_.threaded() && worker_.Queued() > 0);
  const double ms = watch.ElapsedMs();
  const double cpu_ms = ThreadCpuMs() - cpu_start;
  if (!mapper_options_.mask_dir.empty()) {
    const std::string path = fmt::format("{}/{:.6f}.png", mapper_options_.mask_dir, keyframe.timestamp);
    const cv::Mat mask = keyframe.dynamic_mask.empty() ? cv::Mat::zeros(keyframe.depth_m.size(), CV_8U) : keyframe.dynamic_mask;
    if (!cv::imwrite(path, mask)) throw Error("cannot write " + path);
  }
  std::lock_guard<std::mutex> lock(stats_mutex_);
  total_ms_ += ms;
  pose_ms_ += pose_ms;
  cpu_ms_ += cpu_ms;
  max_ms_ = std::max(max_ms_, ms);
  ++processed_;
}

}  // namespace esdslam
