#include "system/run_outputs.h"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>
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

void WriteRunResults(Pipeline& pipeline, const FrameLog& log, const std::string& out_dir) {
  std::string shutdown_error;  // results are written even when local mapping failed
  try {
    pipeline.Finish(out_dir);
  } catch (const Error& e) {
    shutdown_error = e.what();
  }
  const std::filesystem::path out(out_dir);
  const SlamSystem& system = pipeline.system();
  WriteTumTrajectory((out / "trajectory.txt").string(), system.Trajectory());
  WriteTumTrajectory((out / "keyframes.txt").string(), system.KeyFrameTrajectory());
  log.WriteCsv((out / "timing.csv").string());
  SaveRunSettings(pipeline.config().settings, (out / "settings_used.yaml").string());
  if (!shutdown_error.empty()) throw Error(shutdown_error);
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
                             double elapsed_ms) {
  const std::vector<double> lost = log.Values("lost");
  const long tracked = static_cast<long>(lost.size()) - static_cast<long>(Sum(lost));
  std::string text = FormatStageSummary(log);
  text += fmt::format("frames_tracked {} / {} (processed {})\n", tracked, total_frames, log.size());
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
