// `esdslam ghost`: the ghost measure (dense/ghost_measure.h) of a finished run. Reads the run's
// dense.ply and octomap.bt, its trajectory.txt and the sequence's depth images, and prints, for
// the map points and for the occupied OctoMap cells, the fraction of projections that every k-th
// frame sees through by more than the margin. Optionally writes the persistent ghosts (points seen
// through by several frames) as a PLY and a top-view picture of them.
#include <filesystem>
#include <memory>

#include <opencv2/imgcodecs.hpp>

#include "apps/esdslam/commands.h"
#include "common/error.h"
#include "dense/cloud_io.h"
#include "dense/ghost_measure.h"
#include "dense/map_render.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "system/run_settings.h"

namespace esdslam::cli {
namespace {

struct GhostArgs {
  std::string settings_path;
  std::string sequence_dir;
  std::string run_dir;
  std::string trajectory_path;  // default RUN/trajectory.txt
  std::string ghosts_out;       // folder for ghosts.ply and ghosts_top.png
  GhostMeasureOptions options;
};

void PrintStats(const char* what, const GhostStats& stats) {
  std::printf("%s_count %zu\n%s_frames %zu\n%s_projections %zu\n%s_seen_through %zu\n%s_ghost_fraction %.5f\n%s_persistent_ghosts %zu\n",
              what, stats.points, what, stats.frames, what, stats.projections, what, stats.seen_through, what, stats.fraction(),
              what, stats.persistent_ghosts);
  for (std::size_t b = 0; b < stats.residual_count_by_range.size(); ++b)
    if (stats.residual_count_by_range[b] > 0)
      std::printf("%s_residual_m %.1f-%.1f %.4f (%zu)\n", what, b * GhostStats::kRangeBin, (b + 1) * GhostStats::kRangeBin,
                  stats.residual_sum_by_range[b] / stats.residual_count_by_range[b], stats.residual_count_by_range[b]);
}

void WriteGhosts(const std::string& dir, const GhostMeasure& measure, const PointCloud& cloud, int persistent,
                 const std::vector<StampedPose>& trajectory) {
  std::filesystem::create_directories(dir);
  PointCloud ghosts;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (measure.seen_through_counts()[i] >= persistent) ghosts.push_back(cloud.points[i], cloud.colors[i]);
  WritePly(dir + "/ghosts.ply", ghosts);
  std::vector<Rigid3> cams;
  for (const StampedPose& pose : trajectory) cams.push_back(pose.world_from_cam);
  const std::string path = dir + "/ghosts_top.png";
  if (!cv::imwrite(path, RenderTopView(ghosts, cams))) throw Error("cannot write " + path);
}

int RunGhost(const GhostArgs& args) {
  args.options.Check();
  const RunSettings settings = LoadRunSettings(args.settings_path);
  const PinholeCamera camera(settings.core.camera);
  const TumSequence sequence = TumSequence::Open(args.sequence_dir);
  const std::string trajectory_path = args.trajectory_path.empty() ? args.run_dir + "/trajectory.txt" : args.trajectory_path;
  const std::vector<StampedPose> trajectory = ReadTumTrajectory(trajectory_path);
  if (trajectory.empty()) throw InputError(trajectory_path, 0, "trajectory has no poses");
  std::printf("margin_m %.3f\nframe_step %d\n", args.options.margin_m, args.options.frame_step);

  const PointCloud cloud = ReadPly(args.run_dir + "/dense.ply");
  GhostMeasure points(camera, cloud.points, args.options);
  MeasureGhostsOverSequence(&points, trajectory, sequence.frames(), settings.core.depth_map_factor, args.options);
  PrintStats("points", points.stats());
  if (!args.ghosts_out.empty()) WriteGhosts(args.ghosts_out, points, cloud, args.options.persistent_frames, trajectory);

  const std::string octomap_path = args.run_dir + "/octomap.bt";
  if (std::filesystem::exists(octomap_path)) {
    GhostMeasure cells(camera, ReadOccupiedCellCentres(octomap_path), args.options);
    MeasureGhostsOverSequence(&cells, trajectory, sequence.frames(), settings.core.depth_map_factor, args.options);
    PrintStats("cells", cells.stats());
  }
  return 0;
}

RunFn Setup(CLI::App& app) {
  auto args = std::make_shared<GhostArgs>();
  app.add_option("--settings", args->settings_path, "Settings YAML of the run (camera, depth factor)")->required();
  app.add_option("--sequence", args->sequence_dir, "Sequence folder in TUM layout")->required();
  app.add_option("--run", args->run_dir, "Output folder of `esdslam run --dense` or `esdslam map` (dense.ply, octomap.bt)")->required();
  app.add_option("--trajectory", args->trajectory_path, "Poses of the measured frames (default RUN/trajectory.txt)");
  app.add_option("--margin", args->options.margin_m, "Seen through by more than this, metres")->capture_default_str();
  app.add_option("--every", args->options.frame_step, "Measure every k-th pose of the trajectory")->capture_default_str();
  app.add_option("--persistent", args->options.persistent_frames, "A point seen through by this many frames is a persistent ghost")
      ->capture_default_str();
  app.add_option("--ghosts-out", args->ghosts_out, "Write the persistent ghosts here (ghosts.ply, ghosts_top.png)");
  return [args] { return RunGhost(*args); };
}

const Registrar registrar({"ghost", "Ghost measure of a dense map: how much of it later frames see through", Setup, 45});

}  // namespace
}  // namespace esdslam::cli
