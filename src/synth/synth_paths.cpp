#include "synth/synth_paths.h"

#include <algorithm>
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

// Position and heading (rad, continuous) at arc length s in [0, length) along a rounded
// rectangle centred at the origin (half extents a x b, corner radius r), counterclockwise from
// the middle of its south side heading east.
struct PathPoint {
  Vec2 position;
  double heading;
};

double RoundedRectangleLength(double a, double b, double r) { return 4 * (a - r) + 4 * (b - r) + kTwoPi * r; }

PathPoint RoundedRectanglePoint(double a, double b, double r, double s) {
  // Four sides, each a straight part (from the middle of the south side: half of it first)
  // followed by a quarter circle; side k heads k * 90 deg.
  const double straight[4] = {2 * (a - r), 2 * (b - r), 2 * (a - r), 2 * (b - r)};
  const double quarter = 0.5 * M_PI * r;
  Vec2 start(-(a - r), -b);  // the south side's straight part starts here
  s += a - r;                // arc length from that start
  const double length = RoundedRectangleLength(a, b, r);
  if (s >= length) s -= length;
  for (int k = 0; k < 4; ++k) {
    const double heading = k * 0.5 * M_PI;
    const Vec2 forward(std::cos(heading), std::sin(heading)), left(-std::sin(heading), std::cos(heading));
    if (s < straight[k]) return {start + s * forward, heading};
    s -= straight[k];
    const Vec2 end = start + straight[k] * forward;
    if (s < quarter || k == 3) {
      const double angle = std::min(s, quarter) / r;
      const Vec2 centre = end + r * left;
      return {centre - r * std::cos(angle) * left + r * std::sin(angle) * forward, heading + angle};
    }
    s -= quarter;
    start = end + r * forward + r * left;
  }
  return {start, 0.0};  // not reached
}

// A walk along the ring corridor's middle line (options.loop_turns turns of a rounded
// 7.75 x 4.75 m rectangle, 23.3 m per turn), looking ahead with the head turning left and right by up to 17 deg,
// slightly down, with a step bob: a loop through a space much larger than the depth range
// seen at once, revisited after a whole turn. Periodic per turn.
Rigid3 CorridorPose(const SynthOptions& options, double time) {
  constexpr double kHalfX = 3.875, kHalfY = 2.375, kCornerRadius = 1.0;
  const double length = RoundedRectangleLength(kHalfX, kHalfY, kCornerRadius);
  const double turns = options.loop_turns * time / Duration(options);
  const double u = turns - std::floor(turns);  // fraction of the current turn
  const PathPoint point = RoundedRectanglePoint(kHalfX, kHalfY, kCornerRadius, u * length);
  const double steps = std::round(length / 0.7);  // step bob cycles per turn
  const double bob = 0.015 * std::sin(kTwoPi * steps * u);
  const Vec3 position(point.position.x(), point.position.y(), 1.45 + bob);
  const double heading = point.heading + 0.3 * std::sin(kTwoPi * 7 * u);
  const double pitch = -0.12 + 0.05 * std::sin(kTwoPi * 5 * u + 1.0);
  const double roll = 0.03 * std::sin(kTwoPi * 4 * u + 2.0);
  return Rigid3(WorldFromCamRotation(heading, pitch, roll), position);
}

// Fast turns on the spot (TUM fr1_rpy-like hand-held roll, pitch and yaw), looking north at the
// sideboard, crate and picture on the north wall; a few cm of hand jitter. Rates (deg/s) are the
// amplitude times 2 pi f: yaw 43 + 49, pitch 50, roll 55; their sum of squares peaks where the
// phases meet. The turns fade in over the first second from a still start (as a recording
// starts; a tracker cannot correct its first frame's rolling shutter, having no rate yet). A
// function of time only, so rolling-shutter rows can sample it at any instant.
Rigid3 RpyPose(double time) {
  const double t = time;
  constexpr double kFadeIn = 1.0;  // seconds
  const double fade = 0.5 - 0.5 * std::cos(M_PI * std::clamp(t / kFadeIn, 0.0, 1.0));  // 0 -> 1, smooth
  const Vec3 jitter(0.02 * std::sin(kTwoPi * 0.3 * t), 0.015 * std::sin(kTwoPi * 0.45 * t + 1.0),
                    0.01 * std::sin(kTwoPi * 0.6 * t + 2.0));
  const Vec3 position = Vec3(0.0, -0.3, 1.4) + jitter;
  const double heading =
      M_PI / 2 + fade * (0.30 * std::sin(kTwoPi * 0.4 * t + 0.3) + 0.15 * std::sin(kTwoPi * 0.9 * t + 0.51));
  const double pitch = -0.2 + fade * 0.2 * std::sin(kTwoPi * 0.7 * t + 1.0);
  const double roll = fade * 0.28 * std::sin(kTwoPi * 0.55 * t + 2.0);
  return Rigid3(WorldFromCamRotation(heading, pitch, roll), position);
}

}  // namespace

Rigid3 CameraPoseAt(const SynthOptions& options, double time) {
  if (options.trajectory == "rpy") return RpyPose(time);
  if (options.trajectory == "loop") return LoopPose(options, time);
  if (options.trajectory == "orbit") return OrbitPose(options, time);
  if (options.trajectory == "corridor") return CorridorPose(options, time);
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

namespace {

// Where the close pair and the blocker wait when they are not in the scene: under the floor,
// outside the room box, which every camera ray hits first.
Rigid3 ParkedPose() { return Rigid3(Quat::Identity(), Vec3(0.0, 0.0, -50.0)); }

// Seconds -> frame index of the rgb image taken then.
int FrameAt(const SynthOptions& options, double time) { return static_cast<int>(std::lround(time * options.fps)); }

}  // namespace

Vec3 ClosePassHalfSize(const SynthOptions& options) { return Vec3(0.5 * options.close_pass_width, 0.15, 0.9); }

Rigid3 ClosePassPose(const SynthOptions& options, double time) {
  const double u = (time - options.close_pass_time) / options.close_pass_duration;  // 0..1 over the pass
  if (options.close_pass_time < 0 || u < 0 || u > 1) return ParkedPose();
  const Rigid3 world_from_cam = CameraPoseAt(options, time);
  const Mat3 cam_axes = world_from_cam.rotation_matrix();
  const Vec3 forward = Vec3(cam_axes(0, 2), cam_axes(1, 2), 0.0).normalized();  // level heading
  const Vec3 up = Vec3::UnitZ();
  const Vec3 right = forward.cross(up);
  const Vec3 half = ClosePassHalfSize(options);
  // Lateral offset of the pair's centre (metres, + right): from just outside the view (at its
  // back face's depth) to +-5 cm in 20 % of the pass, across the middle 60 %, out in the last 20 %.
  const double half_view = 0.5 * options.intrinsics.width / options.intrinsics.fx;  // tan(half fov)
  const double outside = half_view * (options.close_pass_distance + half.y()) + half.x() + 0.05;
  double lateral;
  if (u < 0.2) {
    lateral = outside + (0.05 - outside) * (u / 0.2);
  } else if (u <= 0.8) {
    lateral = 0.05 - 0.1 * (u - 0.2) / 0.6;
  } else {
    lateral = -0.05 - (outside - 0.05) * ((u - 0.8) / 0.2);
  }
  Vec3 centre = world_from_cam.translation() + forward * options.close_pass_distance + right * lateral;
  centre.z() = half.z();  // standing on the floor
  Mat3 rotation;
  rotation.col(0) = right;
  rotation.col(1) = forward;
  rotation.col(2) = up;
  return Rigid3(Quat(rotation), centre);
}

Vec3 BlockerHalfSize() { return Vec3(0.3, 0.05, 0.3); }

Rigid3 BlockerPose(const SynthOptions& options, double time) {
  const int frame = FrameAt(options, time);
  if (options.blocked_frame < 0 || frame < options.blocked_frame || frame >= options.blocked_frame + options.blocked_frames)
    return ParkedPose();
  // Front face 0.15 m from the lens; its right edge where the image's last 2 % of columns begin.
  const Vec3 half = BlockerHalfSize();
  const double front = 0.15;
  const double edge_column = options.intrinsics.width * 0.98;
  const double edge_x = (edge_column - options.intrinsics.cx) / options.intrinsics.fx * front;
  Mat3 cam_from_box_rotation;  // box x -> camera x, box y -> optical axis, box z -> image up
  cam_from_box_rotation << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  const Rigid3 cam_from_box(Quat(cam_from_box_rotation), Vec3(edge_x - half.x(), 0.0, front + half.y()));
  return CameraPoseAt(options, time) * cam_from_box;
}

}  // namespace esdslam
