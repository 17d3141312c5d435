#pragma once
// Builds the static dense map off the tracking thread. Keyframes (colour, depth, dynamic mask)
// go through a bounded queue to a worker thread that back-projects them into the DenseMap;
// tracking only pays for the hand-off, so its time does not grow with the map.
//
// Threads: the caller (tracking or local mapping) calls AddKeyframe/RemoveKeyframe; one worker
// consumes the queue. Shared data: the queue (its own lock) and the DenseMap (its own lock).
// No lock is held while another is taken.

#include <map>
#include <string>
#include <thread>

#include "common/bounded_queue.h"
#include "dense/dense_map.h"
#include "dense/depth_backprojector.h"

namespace esdslam {

class DenseMapper {
 public:
  // threaded = false processes each keyframe on the caller's thread (deterministic tests).
  DenseMapper(const PinholeCamera& camera, const DenseOptions& options, bool threaded = true);
  ~DenseMapper();
  DenseMapper(const DenseMapper&) = delete;
  DenseMapper& operator=(const DenseMapper&) = delete;

  // Images are shared (cv::Mat reference counting), not copied: callers must not write to them
  // afterwards. dynamic_mask: empty or CV_8U, nonzero = dynamic.
  void AddKeyframe(long keyframe_id, const cv::Mat& bgr, const cv::Mat& depth_m, const cv::Mat& dynamic_mask);
  void RemoveKeyframe(long keyframe_id);
  // Waits until every queued keyframe is in the map and stops the worker. Idempotent.
  void Finish();

  const DenseMap& map() const { return map_; }
  double mean_backprojection_ms() const;

 private:
  struct Job {
    long keyframe_id = 0;
    cv::Mat bgr, depth_m, dynamic_mask;
  };
  void Process(const Job& job);
  void WorkerLoop();

  DepthBackprojector backprojector_;
  DenseMap map_;
  bool threaded_;
  BoundedQueue<Job> queue_{16};
  std::thread worker_;
  mutable std::mutex stats_mutex_;
  double total_ms_ = 0;
  long processed_ = 0;
};

struct DenseOutputFiles {
  bool ply = true;
  bool pcd = false;
  bool octomap = true;
  bool pictures = true;
};

struct DenseOutputSummary {
  std::size_t points = 0;
  std::size_t keyframes = 0;
  std::size_t occupied_leaves = 0;
  double build_ms = 0;
};

// Writes dir/dense.ply (and dense.pcd), dir/octomap.bt, dir/dense_top.png and dir/dense_view.png
// from the map's keyframe clouds at the given keyframe poses.
DenseOutputSummary WriteDenseOutputs(const DenseMap& map, const std::map<long, Rigid3>& world_from_keyframe,
                                     const std::string& dir, const DenseOutputFiles& files = {});

}  // namespace esdslam
