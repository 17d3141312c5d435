#include "dense/dense_mapper.h"

#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <spdlog/spdlog.h>

#include "common/timer.h"
#include "dense/cloud_io.h"
#include "dense/map_render.h"
#include "dense/octomap_writer.h"

namespace esdslam {

DenseMapper::DenseMapper(const PinholeCamera& camera, const DenseOptions& options, bool threaded)
    : backprojector_(camera, options), map_(options), threaded_(threaded) {
  if (threaded_) worker_ = std::thread([this] { WorkerLoop(); });
}

DenseMapper::~DenseMapper() { Finish(); }

void DenseMapper::AddKeyframe(long keyframe_id, const cv::Mat& bgr, const cv::Mat& depth_m, const cv::Mat& dynamic_mask) {
  Job job{keyframe_id, bgr, depth_m, dynamic_mask};
  if (!threaded_) {
    Process(job);
    return;
  }
  if (!queue_.Push(std::move(job))) spdlog::warn("dense: keyframe {} arrived after Finish(); ignored", keyframe_id);
}

void DenseMapper::RemoveKeyframe(long keyframe_id) { map_.RemoveKeyframe(keyframe_id); }

void DenseMapper::Finish() {
  queue_.Close();
  if (worker_.joinable()) worker_.join();
}

double DenseMapper::mean_backprojection_ms() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return processed_ > 0 ? total_ms_ / processed_ : 0.0;
}

void DenseMapper::Process(const Job& job) {
  const Stopwatch watch;
  map_.SetKeyframeCloud(job.keyframe_id, backprojector_.Backproject(job.bgr, job.depth_m, job.dynamic_mask));
  std::lock_guard<std::mutex> lock(stats_mutex_);
  total_ms_ += watch.ElapsedMs();
  ++processed_;
}

void DenseMapper::WorkerLoop() {
  while (auto job = queue_.Pop()) {
    try {
      Process(*job);
    } catch (const std::exception& e) {
      spdlog::error("dense: keyframe {} skipped: {}", job->keyframe_id, e.what());
    }
  }
}

DenseOutputSummary WriteDenseOutputs(const DenseMap& map, const std::map<long, Rigid3>& world_from_keyframe,
                                     const std::string& dir, const DenseOutputFiles& files) {
  const Stopwatch watch;
  std::filesystem::create_directories(dir);
  DenseOutputSummary summary;
  const PointCloud cloud = map.BuildGlobalCloud(world_from_keyframe);
  summary.points = cloud.size();
  summary.keyframes = map.num_keyframes();
  if (files.ply) WritePly(dir + "/dense.ply", cloud);
  if (files.pcd) WritePcd(dir + "/dense.pcd", cloud);
  if (files.octomap) {
    OctomapStats stats;
    if (WriteOctomap(dir + "/octomap.bt", map.PosedClouds(world_from_keyframe), map.options().octomap_resolution,
                     map.options().octomap_max_range, &stats))
      summary.occupied_leaves = stats.occupied_leaves;
  }
  if (files.pictures) {
    std::vector<Rigid3> cams;
    for (const auto& entry : world_from_keyframe) cams.push_back(entry.second);
    MapRenderOptions render;
    render.point_spacing = map.options().voxel_size;
    cv::imwrite(dir + "/dense_top.png", RenderTopView(cloud, cams, render));
    cv::imwrite(dir + "/dense_view.png", RenderPerspectiveView(cloud, cams, render));
  }
  summary.build_ms = watch.ElapsedMs();
  return summary;
}

}  // namespace esdslam
