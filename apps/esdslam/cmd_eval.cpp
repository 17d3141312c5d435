// `esdslam eval GROUNDTRUTH ESTIMATE`: ATE and RPE (TUM benchmark definitions) of a TUM-format
// trajectory against ground truth; optional X-Y plot of both after alignment.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "apps/esdslam/commands.h"
#include "eval/plot.h"
#include "eval/report.h"
#include "io/trajectory_io.h"

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
};

void Plot(const std::vector<StampedPose>& groundtruth, const std::vector<StampedPose>& estimate,
          const AteResult& ate, const std::string& path) {
  std::vector<Vec3> gt_points, est_points;
  for (const auto& pose : groundtruth) gt_points.push_back(pose.world_from_cam.translation());
  for (const auto& pose : estimate) est_points.push_back(ate.groundtruth_from_estimate * pose.world_from_cam.translation());
  PlotTrajectoriesXY(gt_points, est_points, path);
}

int RunEval(const EvalArgs& args) {
  const std::vector<StampedPose> groundtruth = ReadTumTrajectory(args.groundtruth_path);
  const std::vector<StampedPose> estimate = ReadTumTrajectory(args.estimate_path);
  EvalOptions options;
  options.ate.max_time_difference = args.max_dt;
  options.ate.time_offset = args.offset;
  options.ate.with_scale = args.with_scale;
  const EvalReport report = Evaluate(groundtruth, estimate, options);
  const std::string text = args.json ? FormatReportJson(report) : FormatReportText(report);
  std::fputs(text.c_str(), stdout);
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
