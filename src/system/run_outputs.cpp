#include "system/run_outputs.h"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <opencv2/imgcodecs.hpp>

#include "common/error.h"
#include "dynamic/debug_picture.h"
#include "io/trajectory_io.h"

namespace esdslam {

void WriteDebugFrame(const std::string& dir, const FrameReport& report) {
  const cv::Mat picture = DrawDynamicDebugPicture(report.bgr, report.mask.mask, report.geometry_mask(),
                                                  *report.features);
  const std::string path = fmt::format("{}/{:.6f}.png", dir, report.timestamp);
  if (!cv::imwrite(path, picture)) throw Error("cannot write " + path);
}

namespace {

// Runs step; keeps the first Error (or other exception, e.g. cv::Exception) in *first_error.
template <typename Step>
void Try(std::string* first_error, Step&& step) {
  try {
    step();
  } catch (const std::exception& e) {
    spdlog::error("run: {}", e.what());
    if (first_error->empty()) *first_error = e.what();
  }
}

}  // namespace

void WriteRunResults(Pipeline& pipeline, LiveOutputs& live, const std::string& out_dir) {
  std::string error;  // every output is tried, also after a failure; the first one is rethrown
  const SlamSystem& system = pipeline.system();
  Try(&error, [&] { live.WritePoses(system); });  // before any thread is joined
  bool slam_stopped = false;
  Try(&error, [&] {
    pipeline.StopSlam();
    slam_stopped = true;
  });
  if (slam_stopped) Try(&error, [&] { live.WritePoses(system); });  // the final poses
  Try(&error, [&] { SaveRunSettings(pipeline.config().settings, (std::filesystem::path(out_dir) / "settings_used.yaml").string()); });
  const std::string& map_path = pipeline.config().run.save_map;
  if (slam_stopped && !map_path.empty()) Try(&error, [&] { pipeline.system().SaveMap(map_path); });
  Try(&error, [&] { pipeline.Finish(out_dir); });  // the dense thread, then the dense outputs
  if (!error.empty()) throw Error(error);
}

namespace {

double Sum(const std::vector<double>& values) {
  double sum = 0;
  for (double v : values) sum += v;
  return sum;
}

std::string FormatLoopSummary(const LoopClosingStats& loops) {
  std::string text = fmt::format(
      "loops_closed {} (keyframes checked {}, candidates verified {}, global BA {} done / {} aborted)\n",
      loops.loops_closed, loops.keyframes_checked, loops.consistent_candidates, loops.global_ba.completed,
      loops.global_ba.aborted);
  if (loops.keyframes_checked > 0)
    text += fmt::format("loop_timing detection {:.2f} ms/keyframe, verification {:.2f} ms/candidate, global BA {:.0f} ms/run\n",
                        loops.detect_ms / loops.keyframes_checked,
                        loops.consistent_candidates > 0 ? loops.verify_ms / loops.consistent_candidates : 0.0,
                        loops.global_ba.completed > 0 ? loops.global_ba.total_ms / loops.global_ba.completed : 0.0);
  for (const LoopEvent& event : loops.events)
    text += fmt::format("loop keyframe {} -> {} at t={:.3f}: {} inliers, {} matches, correction {:.3f} m {:.2f} deg, {:.0f} ms\n",
                        event.current_id, event.loop_id, event.timestamp, event.inliers, event.matches,
                        event.correction_m, event.correction_deg, event.correct_ms);
  return text;
}

}  // namespace

std::string FormatRunSummary(const FrameLog& log, std::size_t total_frames, const SlamSystem& system,
                             double elapsed_ms, std::size_t frames_unreadable) {
  const std::vector<double> lost = log.Values("lost");
  const long tracked = static_cast<long>(lost.size()) - static_cast<long>(Sum(lost));
  std::string text = FormatStageSummary(log);
  text += fmt::format("frames_tracked {} / {} (processed {})\n", tracked, total_frames, log.size());
  text += fmt::format("frames_coasted {} (blind: too few static keypoints; the motion model's pose)\n",
                      static_cast<long>(Sum(log.Values("coasted"))));
  text += fmt::format("frames_skipped {} (images that could not be read)\n", frames_unreadable);
  text += fmt::format("frames_dropped {} (arrived while the system was busy: frames without a pose)\n",
                      static_cast<long>(Sum(log.Values("dropped_before"))));
  text += fmt::format("fps {:.1f} (frames processed per second of wall time)\n",
                      1000.0 * static_cast<double>(log.size()) / std::max(1.0, elapsed_ms));
  text += fmt::format("points_culled_by_geometry {}\n", static_cast<long>(Sum(log.Values("geometry_culled"))));
  text += fmt::format("keyframes {}\nmap_points {}\n", system.num_keyframes(), system.num_map_points());
  text += fmt::format("relocalizations {}\n", system.relocalizations());
  return text + FormatLoopSummary(system.loop_stats());
}

}  // namespace esdslam
