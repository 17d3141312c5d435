// `esdslam eval GROUNDTRUTH ESTIMATE`: ATE and RPE (TUM benchmark definitions) of a TUM-format
// trajectory against ground truth; optional X-Y plot of both after alignment. With --all-frames
// SEQUENCE every frame of the sequence counts: a frame without a pose (dropped by --live, lost)
// holds the newest pose before it (eval/held_poses.h).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "apps/esdslam/commands.h"
#include <fmt/format.h>

#include "eval/held_poses.h"
#include "eval/plot.h"
#include "eval/report.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"

namespace esdslam::cli {
namespace {

struct EvalArgs {
  std::string groundtruth_path;
  std::string estimate_path;
  bool json = false;
  bool with_scale = false;
  double max_dt = 0.02;
  double offset = 0.0;
  std::string plot_path;
  std::string all_frames_dir;  // TUM-layout sequence whose frames all count; empty = the estimate's poses only
};

// The estimate at every frame of the sequence; logs how many frames had their own pose.
std::vector<StampedPose> HoldAtEveryFrame(const std::vector<StampedPose>& estimate, const std::string& sequence_dir,
                                          std::string* counts) {
  const TumSequence sequence = TumSequence::Open(sequence_dir);
  std::vector<double> times;
  for (const FrameEntry& frame : sequence.frames()) times.push_back(frame.timestamp);
  const HeldTrajectory held = HoldPosesAtFrames(estimate, times);
  *counts = fmt::format("frames {}\nframes_with_pose {}\nframes_held {}\nframes_before_first_pose {}\n", held.frames,
                        held.with_pose, held.held, held.before_first);
  return held.poses;
}

void Plot(const std::vector<StampedPose>& groundtruth, const std::vector<StampedPose>& estimate,
          const AteResult& ate, const std::string& path) {
  std::vector<Vec3> gt_points, est_points;
  for (const auto& pose : groundtruth) gt_points.push_back(pose.world_from_cam.translation());
  for (const auto& pose : estimate) est_points.push_back(ate.groundtruth_from_estimate * pose.world_from_cam.translation());
  PlotTrajectoriesXY(gt_points, est_points, path);
}

int RunEval(const EvalArgs& args) {
  const std::vector<StampedPose> groundtruth = ReadTumTrajectory(args.groundtruth_path);
  std::vector<StampedPose> estimate = ReadTumTrajectory(args.estimate_path);
  std::string counts;  // with --all-frames: how the frames got their poses
  if (!args.all_frames_dir.empty()) estimate = HoldAtEveryFrame(estimate, args.all_frames_dir, &counts);
  EvalOptions options;
  options.ate.max_time_difference = args.max_dt;
  options.ate.time_offset = args.offset;
  options.ate.with_scale = args.with_scale;
  const EvalReport report = Evaluate(groundtruth, estimate, options);
  const std::string text = args.json ? FormatReportJson(report) : FormatReportText(report);
  std::fputs(text.c_str(), stdout);
  std::fputs(counts.c_str(), args.json ? stderr : stdout);  // JSON stays one object
  if (!args.plot_path.empty()) Plot(groundtruth, estimate, report.ate, args.plot_path);
  return 0;
}

RunFn Setup(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  app.add_option("GROUNDTRUTH", args->groundtruth_path, "Ground-truth trajectory (TUM format)")->required();
  app.add_option("ESTIMATE", args->estimate_path, "Estimated trajectory (TUM format)")->required();
  app.add_flag("--json", args->json, "Print the metrics as one JSON object");
  app.add_flag("--scale", args->with_scale, "Align with a similarity (scale too), not a rigid transform");
  app.add_option("--max-dt", args->max_dt, "Max timestamp difference for association, seconds")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--offset", args->offset, "Time offset added to the estimate's timestamps, seconds")
      ->capture_default_str();
  app.add_option("--all-frames", args->all_frames_dir,
                 "ATE over every frame of this TUM-layout sequence: a frame without a pose (dropped by --live, "
                 "lost) takes the newest pose before it; prints frames, frames_with_pose, frames_held")
      ->check(CLI::ExistingDirectory);
  app.add_option("--plot", args->plot_path, "Write an X-Y plot of ground truth and aligned estimate (.png or .svg)")
      ->check(CLI::Validator(
          [](std::string& path) {
            const std::string extension = std::filesystem::path(path).extension().string();
            const bool ok = extension == ".png" || extension == ".PNG" || extension == ".svg" || extension == ".SVG";
            return ok ? std::string() : "plot file must end in .png or .svg: " + path;
          },
          "FILE.png|FILE.svg"));
  return [args] { return RunEval(*args); };
}

const Registrar kRegistrar({"eval", "ATE/RPE of a trajectory against ground truth (TUM benchmark definitions)", Setup,
                            60});

}  // namespace
}  // namespace esdslam::cli
