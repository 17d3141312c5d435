#pragma once
// Known motions of the synthetic scenes. World frame: x east, y north, z up, origin at the
// centre of the room floor (room: x in [-3, 3], y in [-2.5, 2.5], z in [0, 3] metres; the
// corridor's ring floor: x in [-5, 5], y in [-3.5, 3.5], see synth/synth_layout.h).
// Times are seconds since the first frame.

#include <random>
#include <vector>

#include "common/geometry.h"
#include "synth/synth_options.h"

namespace esdslam {

// world_from_cam of the camera (x right, y down, z forward) at `time`.
// "arc": a 2.6 m walk along an arc south of the room centre, heading towards the room centre,
//   with a gentle yaw/pitch/roll wobble and a 1.5 cm step bob (about 0.33 m/s, <= 20 deg/s at
//   the defaults). "loop": options.loop_turns turns around a 0.5 m circle around the room centre,
//   looking outwards; one turn ends exactly at its start pose (all wobble terms are periodic
//   over a turn). "orbit": options.loop_turns turns around a 1.3 m circle around the room
//   centre, looking at the centre and slightly down (about 0.54 m/s and 24 deg/s at 450 frames
//   per turn). "corridor": options.loop_turns walks along the middle of the ring corridor
//   (a rounded 7.75 x 4.75 m rectangle, 23.4 m per turn, counterclockwise from the middle of its
//   south side), looking ahead with the head turning +-17 deg, periodic per turn. "rpy": turns on
//   the spot like TUM fr1_rpy: within 3 cm of (0, -0.3, 1.4) m, heading north +-26 deg (two
//   sinusoids, 0.4 and 0.9 Hz), pitch -11 deg +-11 deg (0.7 Hz), roll +-16 deg (0.55 Hz); at
//   180 frames and 30 fps the rotation rate between frames peaks near 120 deg/s, median near
//   63 deg/s; the turns fade in from a still start over the first second; the north wall is
//   2.8 m away, its sideboard 2.4 m. Not periodic; independent of num_frames (the same motion at
//   every length).
Rigid3 CameraPoseAt(const SynthOptions& options, double time);

// A mover walks back and forth along a lane parallel to the x axis: x(t) = A sin(omega t + phase).
struct MoverPath {
  double lane_y = 0;      // metres
  double amplitude = 1.75;
  double omega = 0.6;     // rad/s; peak speed = amplitude * omega
  double phase = 0;
};

// One path per mover (options.num_movers), lanes chosen so movers never touch each other,
// the furniture or the camera. Seeded by rng (speeds and phases).
std::vector<MoverPath> MakeMoverPaths(const SynthOptions& options, std::mt19937& rng);

// Half sizes (x along the walking direction, y across, z up) of a mover box, metres.
Vec3 MoverHalfSize(const SynthOptions& options);

// Centre of the mover box at `time` (the box is axis-aligned: it walks along x).
Vec3 MoverCentreAt(const MoverPath& path, const Vec3& half_size, double time);

// The pair walking close to the camera (SynthOptions::close_pass_*): half sizes (x across the
// view, y along the camera's level heading, z up) and world_from_box at `time`. Outside the pass
// the box is parked under the floor, where no ray of the room reaches it.
Vec3 ClosePassHalfSize(const SynthOptions& options);
Rigid3 ClosePassPose(const SynthOptions& options, double time);

// The object blocking the lens (SynthOptions::blocked_*): half sizes (x across the view, y along
// the optical axis, z up in the image) and world_from_box at `time`, attached to the camera
// 0.15-0.25 m in front of it during the blocked frames, parked under the floor otherwise.
Vec3 BlockerHalfSize();
Rigid3 BlockerPose(const SynthOptions& options, double time);

}  // namespace esdslam
