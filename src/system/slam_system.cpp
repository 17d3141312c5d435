#include "system/slam_system.h"

#include <spdlog/spdlog.h>

#include "common/error.h"
#include "common/timer.h"
#include "map/keyframe.h"

namespace esdslam {

void SlamOptions::Check() const {
  tracker.Check();
  mapping.Check();
  loop.Check();
  if (geometry_check) geometry.Check();
  if (tracker.localization_only && load_map.empty()) throw Error("slam: localization mode needs a map to load");
  if (tracker.localization_only && !loop.relocalization) throw Error("slam: localization mode needs relocalization");
}

SlamSystem::SlamSystem(const Settings& settings, const SlamOptions& options)
    : settings_(settings), options_(options) {
  settings_.Check();
  options_.Check();
  extractor_ = std::make_unique<OrbExtractor>(settings_.orb);
  rig_ = MakeRgbdRig(settings_.camera, settings_.bf, settings_.th_depth, *extractor_, settings_.readout_time_s);
  map_ = std::make_unique<Map>();
  mapper_ = std::make_unique<LocalMapper>(map_.get(), options_.mapping, !options_.single_thread);
  KeyFrameSink* sink = mapper_.get();
  if (options_.loop.needs_vocabulary()) {
    places_ = std::make_unique<PlaceRecognition>(LoadVocabulary(options_.loop.vocabulary), options_.loop.places);
    indexing_sink_ = std::make_unique<PlaceIndexingSink>(mapper_.get(), places_.get());
    sink = indexing_sink_.get();
  }
  if (options_.loop.relocalization)
    relocalizer_ = std::make_unique<Relocalizer>(places_.get(), options_.loop.relocalizer);
  if (options_.loop.closing && !options_.tracker.localization_only) {
    loop_closer_ = std::make_unique<LoopCloser>(map_.get(), places_.get(), mapper_.get(), options_.loop.closer,
                                                !options_.single_thread);
    mapper_->SetDownstream([closer = loop_closer_.get()](KeyFrame* keyframe) { closer->InsertKeyFrame(keyframe); });
  }
  tracker_ = std::make_unique<Tracker>(map_.get(), sink, options_.tracker);
  tracker_->set_relocalizer(relocalizer_.get());
  if (options_.geometry_check) geometry_filter_ = std::make_unique<GeometryFilter>(options_.geometry);
  if (!options_.load_map.empty()) {
    LoadMap(options_.load_map, rig_, map_.get());
    if (places_) places_->AddMissing(map_->keyframes());
    tracker_->StartInExistingMap();
  }
  mapper_->Start();
  if (loop_closer_) loop_closer_->Start();
  spdlog::info("slam: {} mode, close depth < {:.2f} m, keyframe at least every {} frames, relocalization {}, "
               "loop closing {}",
               options_.single_thread ? "single-thread" : "threaded", rig_->th_depth_m,
               options_.tracker.max_frames_between_keyframes, relocalizer_ ? "on" : "off", loop_closer_ ? "on" : "off");
}

SlamSystem::~SlamSystem() {
  try {
    Shutdown();
  } catch (const std::exception& e) {
    spdlog::error("slam: shutdown failed: {}", e.what());
  }
}

TrackOutcome SlamSystem::TrackRgbd(const cv::Mat& bgr, const cv::Mat& depth_m, double timestamp,
                                   const cv::Mat& dynamic_mask, const cv::Mat& geometry_exempt) {
  if (shut_down_) throw Error("slam: TrackRgbd after Shutdown");
  TrackOutcome outcome;
  Stopwatch watch;
  Frame frame(next_frame_id_++, timestamp, bgr, depth_m, dynamic_mask, *extractor_, rig_, options_.frame);
  frame.geometry_exempt = geometry_exempt;
  outcome.extract_ms = watch.ElapsedMs();
  watch.Restart();
  GeometryFilterHook geometry(geometry_filter_.get());  // this call's check statistics
  const TrackingResult result = tracker_->Track(&frame, geometry_filter_ ? &geometry : nullptr);
  outcome.geometry = geometry.stats();
  if (options_.single_thread) {
    mapper_->ProcessQueued();
    if (loop_closer_) loop_closer_->ProcessQueued();
  }
  outcome.track_ms = watch.ElapsedMs();
  outcome.state = result.state;
  outcome.has_pose = result.has_pose;
  outcome.new_keyframe = result.new_keyframe != nullptr;
  outcome.keyframe = result.new_keyframe;
  outcome.inliers = result.inliers;
  outcome.coasted = result.coasted;
  FrameRecord record{timestamp, nullptr, Rigid3()};
  if (result.has_pose) {
    outcome.world_from_cam = result.cam_from_world.inverse();
    record.reference = result.reference_keyframe;
    record.cam_from_reference = result.cam_from_world * result.reference_keyframe->world_from_cam();
  }
  std::lock_guard<std::mutex> lock(records_mutex_);
  records_.push_back(record);
  return outcome;
}

int SlamSystem::RemovePointsUnder(KeyFrame* keyframe, const cv::Mat& mask) {
  if (keyframe == nullptr || mask.empty()) return 0;
  if (mask.type() != CV_8UC1) throw Error("RemovePointsUnder: the mask must be CV_8UC1");
  std::lock_guard<std::mutex> lock(map_->update_mutex());
  if (keyframe->is_bad()) return 0;
  const FeatureSet& features = keyframe->features();
  std::vector<int> masked;
  int removed = 0;
  for (int i = 0; i < features.size(); ++i) {
    if (!KeypointOnMask(features.keypoints[i], mask)) continue;
    masked.push_back(i);
    MapPoint* point = keyframe->map_point(i);
    if (point == nullptr || point->is_bad()) continue;
    point->SetBad();
    ++removed;
  }
  keyframe->MarkLateDynamic(masked);  // local mapping and loop closing leave them alone from now on
  return removed;
}

void SlamSystem::Shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  std::string error;  // loop closing is still finished when local mapping failed
  try {
    mapper_->Close();
  } catch (const Error& e) {
    error = e.what();
  }
  try {
    if (loop_closer_) loop_closer_->Close();
  } catch (const Error& e) {
    if (error.empty()) error = e.what();
  }
  const LocalMapperStats stats = mapper_->stats();
  spdlog::debug("local mapping: {} keyframes, {} points created, {} culled, {} keyframes culled, {} BA ({} aborted)",
                stats.keyframes_processed, stats.points_created, stats.points_culled, stats.keyframes_culled,
                stats.bundle_adjustments, stats.bundle_adjustments_aborted);
  if (loop_closer_) {
    const LoopClosingStats loops = loop_closer_->stats();
    spdlog::info("loop closing: {} keyframes checked, {} consistent candidates, {} loops closed, global BA {} "
                 "completed / {} aborted",
                 loops.keyframes_checked, loops.consistent_candidates, loops.loops_closed, loops.global_ba.completed,
                 loops.global_ba.aborted);
  }
  if (!error.empty()) throw Error(error);
}

LoopClosingStats SlamSystem::loop_stats() const { return loop_closer_ ? loop_closer_->stats() : LoopClosingStats{}; }

MapFileSummary SlamSystem::SaveMap(const std::string& path) {
  std::lock_guard<std::mutex> lock(map_->update_mutex());
  const MapFileSummary summary = esdslam::SaveMap(*map_, path);
  spdlog::info("slam: saved {} keyframes, {} points to {}", summary.keyframes, summary.map_points, path);
  return summary;
}

std::vector<StampedPose> SlamSystem::Trajectory() const {
  std::lock_guard<std::mutex> map_lock(map_->update_mutex());
  std::lock_guard<std::mutex> lock(records_mutex_);
  std::vector<StampedPose> poses;
  for (const FrameRecord& record : records_) {
    if (record.reference == nullptr) continue;
    Rigid3 cam_from_reference = record.cam_from_reference;
    KeyFrame* reference = LiveAncestor(record.reference, &cam_from_reference);
    poses.push_back({record.timestamp, (cam_from_reference * reference->cam_from_world()).inverse()});
  }
  return poses;
}

std::vector<StampedPose> SlamSystem::KeyFrameTrajectory() const {
  std::lock_guard<std::mutex> map_lock(map_->update_mutex());
  std::vector<StampedPose> poses;
  for (KeyFrame* keyframe : map_->keyframes()) poses.push_back({keyframe->timestamp(), keyframe->world_from_cam()});
  return poses;
}

}  // namespace esdslam
