#include "system/live_outputs.h"

#include <filesystem>

#include "io/trajectory_io.h"
#include "system/frame_columns.h"

namespace esdslam {

LiveOutputs::LiveOutputs(const std::string& out_dir)
    : trajectory_path_((std::filesystem::path(out_dir) / "trajectory.txt").string()),
      keyframes_path_((std::filesystem::path(out_dir) / "keyframes.txt").string()),
      trajectory_(trajectory_path_),
      keyframes_(keyframes_path_),
      timing_((std::filesystem::path(out_dir) / "timing.csv").string()) {
  trajectory_.Append(kTumTrajectoryHeader);
  keyframes_.Append(kTumTrajectoryHeader);
  timing_.Append(FrameCsvHeader() + "\n");
}

void LiveOutputs::Add(const FrameReport& report, const std::vector<double>& timing_row) {
  timing_.Append(FrameCsvRow(timing_row) + "\n");
  if (!report.track.has_pose) return;
  const std::string line = FormatTumPoseLine({report.timestamp, report.track.world_from_cam});
  trajectory_.Append(line);
  if (report.track.new_keyframe) keyframes_.Append(line);  // a new keyframe has the frame's pose
}

void LiveOutputs::WritePoses(const SlamSystem& system) {
  // The appending handles are closed first: the files are replaced by a rename, and a later
  // Add must not write into the replaced files.
  trajectory_.Close();
  keyframes_.Close();
  WriteTumTrajectory(trajectory_path_, system.Trajectory());
  WriteTumTrajectory(keyframes_path_, system.KeyFrameTrajectory());
}

}  // namespace esdslam
