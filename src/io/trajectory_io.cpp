#include "io/trajectory_io.h"

#include <cstdio>
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

void WriteTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ignored;
  if (!parent.empty()) std::filesystem::create_directories(parent, ignored);
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (!file) throw Error("cannot write trajectory file " + path);
  std::fprintf(file, "# timestamp tx ty tz qx qy qz qw (world_from_cam)\n");
  for (const StampedPose& pose : poses) {
    const Vec3& t = pose.world_from_cam.translation();
    const Quat& q = pose.world_from_cam.rotation();
    // "+ 0.0" turns -0 into 0 so files do not show "-0".
    std::fprintf(file, "%.6f %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", pose.timestamp, t.x() + 0.0, t.y() + 0.0, t.z() + 0.0,
                 q.x() + 0.0, q.y() + 0.0, q.z() + 0.0, q.w() + 0.0);
  }
  const bool failed = std::ferror(file) != 0;
  if (std::fclose(file) != 0 || failed) throw Error("error while writing trajectory file " + path);
}

}  // namespace esdslam
