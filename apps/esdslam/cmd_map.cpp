// `esdslam map`: rebuilds the static dense map (PLY/PCD, OctoMap, PNG views) from a saved
// trajectory (dense_keyframes.txt, keyframes.txt or trajectory.txt of a run) and the sequence's
// images. Dynamic pixels are left out using per-frame masks saved by a run (`--masks DIR`, files
// <timestamp>.png, nonzero = dynamic); without masks every valid depth pixel is used. Prints the
// map's size, time per keyframe, final build time and memory.
#include <cmath>
#include <filesystem>
#include <memory>

#include <opencv2/imgcodecs.hpp>
#include <spdlog/spdlog.h>

#include "apps/esdslam/commands.h"
#include "common/error.h"
#include "dense/dense_mapper.h"
#include "io/settings.h"
#include "io/settings_table.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "system/run_settings.h"

namespace esdslam::cli {
namespace {

struct MapArgs {
  std::string settings_path;
  std::string sequence_dir;
  std::string trajectory_path;
  std::string masks_dir;
  std::string out_dir = "map_out";
  bool pcd = false;
  double max_dt = 0.02;
};

cv::Mat LoadMask(const std::string& masks_dir, const FrameEntry& frame) {
  if (masks_dir.empty()) return cv::Mat();
  const std::string path = fmt::format("{}/{:.6f}.png", masks_dir, frame.timestamp);
  if (!std::filesystem::exists(path)) throw InputError(path, 0, "no dynamic mask for this keyframe (expected <timestamp>.png)");
  cv::Mat mask = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (mask.empty()) throw InputError(path, 0, "unreadable mask image");
  return mask;
}

int RunMap(const MapArgs& args) {
  const RunSettings run_settings = LoadRunSettings(args.settings_path);  // one key table for every stage
  const Settings& settings = run_settings.core;
  const DenseOptions& dense_options = run_settings.dense;

  const TumSequence sequence = TumSequence::Open(args.sequence_dir);
  const std::vector<StampedPose> poses = ReadTumTrajectory(args.trajectory_path);
  if (poses.empty()) throw InputError(args.trajectory_path, 0, "trajectory has no poses");
  // Poses are fixed here, so the worker (which overlaps image loading with integration) gives the
  // same map as a single-threaded build.
  DenseMapper mapper(PinholeCamera(settings.camera), dense_options);
  long id = 0;
  for (const StampedPose& pose : poses) {
    const FrameEntry* frame = NearestFrame(sequence.frames(), pose.timestamp, args.max_dt);
    if (!frame) {
      spdlog::warn("map: no frame within {} s of pose {:.6f}; skipped", args.max_dt, pose.timestamp);
      continue;
    }
    const RgbdImages images = LoadRgbd(*frame, settings.depth_map_factor);
    mapper.AddKeyframe({id++, pose.timestamp, pose.world_from_cam, images.bgr, images.depth_m, LoadMask(args.masks_dir, *frame)});
    std::fprintf(stderr, "\rmap: %ld/%zu poses", id, poses.size());
  }
  std::fprintf(stderr, "\n");
  mapper.Finish();
  DenseOutputFiles files;
  files.pcd = args.pcd;
  const DenseOutputSummary summary = mapper.WriteOutputs(args.out_dir, files);
  const DenseMapperStats stats = mapper.stats();
  std::printf("dense_points %zu\nkeyframes %zu\noctomap_occupied_leaves %zu\noctomap_free_leaves %zu\n", summary.points,
              summary.keyframes, summary.occupied_leaves, summary.free_leaves);
  std::printf("keyframe_ms_mean %.1f\nkeyframe_ms_max %.1f\nkeyframe_cpu_ms_mean %.1f\nbuild_ms %.1f\ncloud_ms %.1f\noctomap_ms %.1f\n",
              stats.mean_keyframe_ms, stats.max_keyframe_ms, stats.mean_keyframe_cpu_ms, summary.build_ms, summary.cloud_ms,
              summary.octomap_ms);
  std::printf("map_points_stored %zu\nmap_bytes %zu\nray_bytes %zu\n", stats.map.points, stats.map.point_bytes,
              stats.map.ray_bytes);
  return 0;
}

RunFn Setup(CLI::App& app) {
  auto args = std::make_shared<MapArgs>();
  app.add_option("--settings", args->settings_path, "Settings YAML (ORB-SLAM2 keys plus Dense.*)")->required();
  app.add_option("--sequence", args->sequence_dir, "Sequence folder in TUM layout")->required();
  app.add_option("--trajectory", args->trajectory_path, "TUM trajectory whose poses become map keyframes (e.g. keyframes.txt)")
      ->required();
  app.add_option("--masks", args->masks_dir, "Folder of dynamic masks <timestamp>.png saved by `esdslam run --dense`");
  app.add_option("--out", args->out_dir, "Output folder")->capture_default_str();
  app.add_flag("--pcd", args->pcd, "Also write dense.pcd");
  app.add_option("--max-dt", args->max_dt, "Max |dt| between a pose and its frame, seconds")->capture_default_str();
  return [args] { return RunMap(*args); };
}

const Registrar registrar({"map", "Rebuild the static dense map from a saved trajectory and the sequence", Setup, 40});

}  // namespace
}  // namespace esdslam::cli
