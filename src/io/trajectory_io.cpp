#include "io/trajectory_io.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "io/text_lines.h"

namespace esdslam {
namespace {

constexpr const char* kFieldNames[8] = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};

StampedPose ParsePoseLine(const TextLine& line, const std::string& path) {
  if (line.fields.size() != 8) {
    throw InputError(path, line.line_number,
                     fmt::format("expected 8 fields 'timestamp tx ty tz qx qy qz qw', got {}", line.fields.size()));
  }
  double values[8];
  for (int i = 0; i < 8; ++i) values[i] = ParseFiniteReal(line.fields[i], kFieldNames[i], path, line.line_number);
  const Quat rotation(values[7], values[4], values[5], values[6]);  // Eigen: (w, x, y, z)
  if (!(rotation.norm() > 1e-6)) {
    throw InputError(path, line.line_number, "quaternion has (near) zero norm and cannot be normalised");
  }
  StampedPose pose;
  pose.timestamp = values[0];
  pose.world_from_cam = Rigid3(rotation, Vec3(values[1], values[2], values[3]));  // normalises
  return pose;
}

}  // namespace

std::vector<StampedPose> ReadTumTrajectory(const std::string& path) {
  const std::vector<TextLine> lines = ReadTextLines(path);
  std::vector<StampedPose> poses;
  std::vector<double> timestamps;
  std::vector<int> line_numbers;
  poses.reserve(lines.size());
  for (const TextLine& line : lines) {
    poses.push_back(ParsePoseLine(line, path));
    timestamps.push_back(poses.back().timestamp);
    line_numbers.push_back(line.line_number);
  }
  CheckStrictlyIncreasing(timestamps, line_numbers, path);
  return poses;
}

std::string FormatTumPoseLine(const StampedPose& pose) {
  const Vec3& t = pose.world_from_cam.translation();
  const Quat& q = pose.world_from_cam.rotation();
  // "+ 0.0" turns -0 into 0 so files do not show "-0".
  char line[256];
  const int n = std::snprintf(line, sizeof(line), "%.6f %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", pose.timestamp, t.x() + 0.0,
                              t.y() + 0.0, t.z() + 0.0, q.x() + 0.0, q.y() + 0.0, q.z() + 0.0, q.w() + 0.0);
  return std::string(line, static_cast<std::size_t>(std::clamp(n, 0, static_cast<int>(sizeof(line)) - 1)));
}

void WriteTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ignored;
  if (!parent.empty()) std::filesystem::create_directories(parent, ignored);
  // Written beside, then renamed over the file: a failed write (full disk, file-size limit)
  // leaves the previous file as it was.
  const std::string temp = path + ".partial";
  std::FILE* file = std::fopen(temp.c_str(), "w");
  if (!file) throw Error(fmt::format("cannot write trajectory file {}: {}", path, std::strerror(errno)));
  std::string text = kTumTrajectoryHeader;
  for (const StampedPose& pose : poses) text += FormatTumPoseLine(pose);
  const bool written = std::fwrite(text.data(), 1, text.size(), file) == text.size() && std::fflush(file) == 0;
  const int write_errno = errno;
  if (std::fclose(file) != 0 || !written) {
    std::remove(temp.c_str());
    throw Error(fmt::format("error while writing trajectory file {}: {}", path, std::strerror(write_errno)));
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0)
    throw Error(fmt::format("cannot replace trajectory file {}: {}", path, std::strerror(errno)));
}

}  // namespace esdslam
