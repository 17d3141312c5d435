#include "synth/synth_paths.h"

#include <cmath>
#include <random>

namespace esdslam {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;

// Camera orientation from heading (angle of the viewing direction in the xy plane from +x),
// pitch (up positive) and roll (about the viewing direction), all radians.
Mat3 WorldFromCamRotation(double heading, double pitch, double roll) {
  const Vec3 forward(std::cos(pitch) * std::cos(heading), std::cos(pitch) * std::sin(heading), std::sin(pitch));
  const Vec3 level_right(std::sin(heading), -std::cos(heading), 0.0);
  const Vec3 level_down = forward.cross(level_right);
  const Vec3 right = std::cos(roll) * level_right + std::sin(roll) * level_down;
  const Vec3 down = forward.cross(right);
  Mat3 rotation;
  rotation.col(0) = right;
  rotation.col(1) = down;
  rotation.col(2) = forward;
  return rotation;
}

double Duration(const SynthOptions& options) {
  return options.num_frames > 1 ? (options.num_frames - 1) / options.fps : 1.0;
}

Rigid3 ArcPose(const SynthOptions& options, double time) {
  const double s = time / Duration(options);
  const double radius = 2.6;
  const Vec3 arc_centre(0.0, 1.0, 0.0);
  const double beta = -0.5 + 1.0 * s;  // rad along the arc
  const double step_bob = 0.015 * std::sin(kTwoPi * 1.6 * time);
  const Vec3 position = arc_centre + Vec3(radius * std::sin(beta), -radius * std::cos(beta), 1.45 + step_bob);
  const double heading = M_PI / 2 + beta + 0.08 * std::sin(kTwoPi * 0.4 * time);
  const double pitch = -0.15 + 0.04 * std::sin(kTwoPi * 0.3 * time + 1.0);
  const double roll = 0.03 * std::sin(kTwoPi * 0.25 * time + 2.0);
  return Rigid3(WorldFromCamRotation(heading, pitch, roll), position);
}

Rigid3 LoopPose(const SynthOptions& options, double time) {
  const double s = options.loop_turns * time / Duration(options);  // turns done: 0 .. loop_turns
  const double alpha = kTwoPi * s;
  const double radius = 0.5;
  const double bob = 0.015 * std::sin(kTwoPi * 24 * s);
  const Vec3 position(radius * std::cos(alpha), radius * std::sin(alpha), 1.45 + bob);
  const double heading = alpha + 0.05 * std::sin(kTwoPi * 3 * s);
  const double pitch = -0.1 + 0.04 * std::sin(kTwoPi * 4 * s);
  const double roll = 0.03 * std::sin(kTwoPi * 3 * s);
  return Rigid3(WorldFromCamRotation(heading, pitch, roll), position);
}

// A walk around a 1.3 m circle about the room centre, looking at the centre and slightly down
// (the far half of the room 3.5-4.5 m away, floor and furniture nearer): rotation and
// translation together, near and far points, as when scanning a room. Periodic per turn.
Rigid3 OrbitPose(const SynthOptions& options, double time) {
  const double s = options.loop_turns * time / Duration(options);  // turns done
  const double alpha = kTwoPi * s;
  const double radius = 1.3;
  const double bob = 0.015 * std::sin(kTwoPi * 24 * s);
  const Vec3 position(radius * std::sin(alpha), -radius * std::cos(alpha), 1.45 + bob);
  const double heading = M_PI / 2 + alpha + 0.06 * std::sin(kTwoPi * 3 * s);
  const double pitch = -0.2 + 0.04 * std::sin(kTwoPi * 4 * s);
  const double roll = 0.03 * std::sin(kTwoPi * 3 * s);
  return Rigid3(WorldFromCamRotation(heading, pitch, roll), position);
}

}  // namespace

Rigid3 CameraPoseAt(const SynthOptions& options, double time) {
  if (options.trajectory == "loop") return LoopPose(options, time);
  if (options.trajectory == "orbit") return OrbitPose(options, time);
  return ArcPose(options, time);
}

Vec3 MoverHalfSize(const SynthOptions& options) {
  return Vec3(0.15, 0.25, 0.85) * options.mover_scale;
}

std::vector<MoverPath> MakeMoverPaths(const SynthOptions& options, std::mt19937& rng) {
  // Lanes >= 0.6 m apart (movers are <= 0.6 m wide), clear of the camera path and furniture.
  static const double kArcLanes[] = {0.8, 0.2, 1.45, -0.4};
  static const double kLoopLanes[] = {1.2, -1.2, 1.8, -1.8};
  const double* lanes = options.trajectory == "loop" ? kLoopLanes : kArcLanes;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<MoverPath> paths;
  for (int k = 0; k < options.num_movers; ++k) {
    MoverPath path;
    path.lane_y = lanes[k];
    path.amplitude = 1.75;
    const double speed = options.mover_speed * (0.8 + 0.4 * unit(rng));
    path.omega = speed / path.amplitude;
    // Start within about 1 m of the lane centre (in view early on), alternate directions.
    path.phase = (k % 2 == 1 ? M_PI : 0.0) + 0.6 * (2.0 * unit(rng) - 1.0);
    paths.push_back(path);
  }
  return paths;
}

Vec3 MoverCentreAt(const MoverPath& path, const Vec3& half_size, double time) {
  return Vec3(path.amplitude * std::sin(path.omega * time + path.phase), path.lane_y, half_size.z());
}

}  // namespace esdslam
