#include "viewer/live_viewer.h"

#include <spdlog/spdlog.h>

#include "viewer/viewer_json.h"

namespace esdslam {

LiveViewer::LiveViewer(const ViewerOptions& options, SlamSystem* system, const DenseMapper* dense, bool serve)
    : options_(options), system_(system), dense_(dense),
      trail_(static_cast<std::size_t>(options.max_dynamic_points)),
      culled_trail_(static_cast<std::size_t>(options.max_dynamic_points)) {
  options_.Check();
  if (serve) server_ = std::make_unique<ViewerServer>(options_, &hub_);
  worker_ = std::make_unique<Worker<Job>>("viewer", WorkerMode::kThread, options_.queue_capacity,
                                         [this](Job& job) { Handle(job); });
  worker_->Start();
  if (server_) spdlog::info("viewer: watch the run at {}", server_->url());
}

LiveViewer::~LiveViewer() {
  try {
    Close();
  } catch (const std::exception& e) {
    spdlog::error("viewer: {}", e.what());
  }
}

void LiveViewer::Offer(const FrameReport& report) {
  if (failed_) return;
  ++offered_;
  dropped_total_ += report.dropped_before;
  const std::vector<Vec3>& culled = report.track.geometry.culled_positions;
  if (!culled.empty()) {
    std::lock_guard<std::mutex> lock(culled_mutex_);
    for (const Vec3& p : culled) culled_pending_.push_back(p.cast<float>());
    const std::size_t cap = static_cast<std::size_t>(options_.max_dynamic_points);
    if (culled_pending_.size() > cap) culled_pending_.erase(culled_pending_.begin(), culled_pending_.end() - cap);
  }
  last_report_ = report;  // headers and shared pointers only
  const double now_ms = run_clock_.ElapsedMs();
  if (now_ms - last_offer_ms_ < options_.frame_interval_ms) {
    ++skipped_;
    return;
  }
  last_offer_ms_ = now_ms;
  Job job{report, dropped_total_, now_ms, skipped_ + dropped_, false};
  try {
    if (worker_->PushDropOldest(std::move(job)) == DropOldestPush::kQueuedDroppedOldest) ++dropped_;
  } catch (const std::exception& e) {  // the viewer failed: the run goes on without it
    spdlog::error("viewer: {}; the run goes on without the viewer", e.what());
    failed_ = true;
  }
}

void LiveViewer::Finish() {
  if (failed_) return;
  Job job;
  if (last_report_) job.report = *last_report_;
  job.dropped_total = dropped_total_;
  job.run_ms = run_clock_.ElapsedMs();
  job.viewer_dropped = skipped_ + dropped_;
  job.final = true;
  worker_->Push(std::move(job));
  worker_->Drain();
  worker_->ThrowIfFailed();
}

void LiveViewer::Close() {
  if (worker_) worker_->Close();
  if (server_) server_->Stop();
  hub_.Close();
}

ViewerStats LiveViewer::stats() const {
  ViewerStats s;
  s.offered = offered_;
  s.skipped = skipped_;
  s.dropped = dropped_;
  s.encoded = encoded_;
  s.maps = maps_;
  s.frame_cpu_ms = frame_cpu_ms_;
  s.map_cpu_ms = map_cpu_ms_;
  return s;
}

void LiveViewer::Handle(Job& job) {
  RunCounters counters;
  counters.frames = static_cast<long>(job.report.index) + 1;
  counters.dropped = job.dropped_total;
  counters.keyframes = system_ != nullptr ? system_->num_keyframes() : 0;
  counters.map_points = system_ != nullptr ? system_->num_map_points() : 0;
  counters.fps = job.run_ms > 0 ? 1000.0 * static_cast<double>(counters.frames) / job.run_ms : 0;
  counters.viewer_dropped = job.viewer_dropped;
  const bool has_frame = job.report.features != nullptr || !job.report.bgr.empty();
  if (has_frame) {
    const ThreadCpuStopwatch cpu;
    trail_.Add(job.report);
    hub_.Publish("frame", EncodeFrameEvent(job.report, counters, options_));
    ++encoded_;
    frame_cpu_ms_ = frame_cpu_ms_ + cpu.ElapsedMs();  // this thread is the only writer
  }
  if (job.final || !map_published_ || map_clock_.ElapsedMs() >= options_.map_interval_ms) PublishMap(job.final);
  if (job.final) {
    JsonText status;
    status.BeginObject().Bool("finished", true).Integer("frames", has_frame ? counters.frames : 0).EndObject();
    hub_.Publish("status", status.Take());
  }
}

void LiveViewer::PublishMap(bool finished) {
  const ThreadCpuStopwatch cpu;
  MapView view = system_ != nullptr ? ReadMapView(*system_, options_) : MapView();
  view.dynamic_points = trail_.Points();
  {
    std::vector<Eigen::Vector3f> culled;
    {
      std::lock_guard<std::mutex> lock(culled_mutex_);
      culled.swap(culled_pending_);
    }
    culled_trail_.Add(culled);
  }
  view.culled_points = culled_trail_.Points();
  view.dense = DenseCloud(finished);
  view.finished = finished;
  DecimateMapView(options_, &view);
  hub_.Publish("map", EncodeMapEvent(view));
  ++maps_;
  map_published_ = true;
  map_clock_.Restart();
  map_cpu_ms_ = map_cpu_ms_ + cpu.ElapsedMs();
}

const PointCloud& LiveViewer::DenseCloud(bool finished) {
  if (dense_ == nullptr) return dense_cloud_;
  const long keyframes = static_cast<long>(dense_->stats().keyframes);
  const bool due = dense_keyframes_ < 0 || finished || dense_clock_.ElapsedMs() >= options_.dense_interval_ms;
  if (!due || (keyframes == dense_keyframes_ && !finished)) return dense_cloud_;
  MapView thin;
  thin.dense = dense_->CurrentCloud();
  DecimateMapView(options_, &thin);
  dense_cloud_ = std::move(thin.dense);
  dense_keyframes_ = keyframes;
  dense_clock_.Restart();
  return dense_cloud_;
}

}  // namespace esdslam
