#pragma once
// The result files of a run that grow while it goes, so that a run stopped at any moment (a
// signal, a kill, a full disk) leaves every frame tracked so far on disk (README "Outputs"):
//   OUT/trajectory.txt  a pose line per frame that got a pose, the pose as tracked (world_from_cam)
//   OUT/keyframes.txt   a pose line per new keyframe, its pose when it was made
//   OUT/timing.csv      the header, then a row per frame processed (system/frame_columns.h)
// Each file is appended and handed to the operating system after every frame (io/append_file.h).
// At the end of the run WriteFinalPoses replaces trajectory.txt and keyframes.txt by the final
// poses (after local mapping, loop closing and global BA moved them); timing.csv is final as it is.
// A write error is an Error naming the file; the files keep every frame before it.

#include <string>
#include <vector>

#include "io/append_file.h"
#include "system/frame_report.h"
#include "system/slam_system.h"

namespace esdslam {

class LiveOutputs {
 public:
  // Creates (truncates) the three files in out_dir, each with its header. Throws Error.
  explicit LiveOutputs(const std::string& out_dir);

  // One frame: its timing row (FrameLog::row, the column table's values) and, when it got a
  // pose or made a keyframe, its pose lines. Throws Error naming the file that cannot be written.
  void Add(const FrameReport& report, const std::vector<double>& timing_row);

  // Replaces trajectory.txt and keyframes.txt by the system's poses now (every frame at its
  // reference keyframe's current pose; the live keyframes). The files are replaced whole or not
  // at all (io/trajectory_io.h). Throws Error naming the file.
  void WritePoses(const SlamSystem& system);

  const std::string& trajectory_path() const { return trajectory_path_; }
  const std::string& keyframes_path() const { return keyframes_path_; }

 private:
  std::string trajectory_path_, keyframes_path_;
  AppendFile trajectory_, keyframes_, timing_;
};

}  // namespace esdslam
