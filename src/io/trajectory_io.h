#pragma once
// Trajectories in the TUM RGB-D benchmark text format: one pose per line,
// 'timestamp tx ty tz qx qy qz qw' (seconds; metres; unit quaternion, Hamilton, w last), the
// pose being world_from_cam. Lines starting with '#' and blank lines are comments.

#include <string>
#include <vector>

#include "common/geometry.h"

namespace esdslam {

struct StampedPose {
  double timestamp = 0;  // seconds
  Rigid3 world_from_cam;
};

// Throws InputError(file, line, what) on: missing/unreadable file, a line without exactly 8
// fields (separators: spaces, tabs or commas), a non-numeric field, NaN/inf, timestamps not
// strictly increasing (unsorted or duplicate), a quaternion whose norm is ~0. Quaternions are
// normalised. An empty file gives an empty vector.
std::vector<StampedPose> ReadTumTrajectory(const std::string& path);

// The first line of every trajectory file written here.
inline constexpr const char* kTumTrajectoryHeader = "# timestamp tx ty tz qx qy qz qw (world_from_cam)\n";

// One pose line, newline included: timestamp with 6 decimals, pose values with 9 significant digits.
std::string FormatTumPoseLine(const StampedPose& pose);

// Writes the header and FormatTumPoseLine of every pose into PATH.partial, then renames it over
// PATH (a failed write leaves an existing PATH unchanged). Creates the parent folder if needed.
// Throws Error naming the file and the system's reason when it cannot be written.
void WriteTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses);

}  // namespace esdslam
