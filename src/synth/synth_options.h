#pragma once
// Options of the synthetic RGB-D scene generator (see synth/synthetic_scene.h).
//
// The scene is a textured 6 x 5 x 3 m room with static furniture; the camera follows a known
// smooth path ("arc": a walk along an arc looking into the room; "loop": a small circle looking
// outwards; "orbit": a walk around the room centre looking at it; "corridor": a walk around a
// ring corridor on a larger floor (synth/synth_layout.h); loop, orbit and corridor make
// `loop_turns` turns over the sequence, one turn ending exactly at its start pose; "rpy": fast
// roll, pitch and yaw turns on the spot, like TUM fr1_rpy); optional human-sized boxes walk back
// and forth through the view. The colour and depth images can have a rolling shutter
// (`readout_time_s`). Everything is deterministic given `seed`.

#include <cstdint>
#include <string>

#include "camera/pinhole_camera.h"

namespace esdslam {

struct SynthOptions {
  int num_frames = 240;
  std::uint32_t seed = 1;
  double fps = 30.0;                // frame rate; timestamps are first_timestamp + i / fps
  double first_timestamp = 100.0;   // seconds
  // Pinhole camera without distortion (k1..k3 = 0 are required). Default: 640x480, f = 525.
  CameraIntrinsics intrinsics = DefaultIntrinsics();
  // "arc", "loop", "orbit", "corridor" or "rpy" (orbit, corridor, rpy: no movers). rpy: the
  // camera stays within a few cm of a point 1.4 m above the floor and turns about roll, pitch and
  // yaw with sinusoids of different frequencies, fading in over the first second (then up to
  // about 120 deg/s, median about 63 deg/s at 30 fps), looking at the north wall and its
  // furniture 2.4-4 m away (synth/synth_paths.h).
  std::string trajectory = "arc";
  // Loop and orbit: turns around the circle over the sequence (the path is periodic per turn). More
  // than 1 revisits the start: the place is seen again for (turns - 1) of a turn.
  double loop_turns = 1.0;
  int num_movers = 0;               // moving people (boxes); 0 = static scene. arc: <= 4, loop: <= 4
  double mover_scale = 1.0;         // size factor of a mover (1 = 0.5 wide x 0.3 deep x 1.7 m tall)
  double mover_speed = 1.1;         // mean walking speed, m/s (each mover varies +-20 %)
  // Gaussian depth noise: sigma(z) = depth_noise_at_1m * z^2 metres (Kinect-like growth).
  // 0 = exact depth (only the 1/5000 m quantisation of the PNG files remains).
  double depth_noise_at_1m = 0.0;
  // Gaussian colour noise of the sensor, grey levels per channel and pixel (0 = none).
  double image_noise_sigma = 0.0;
  double max_depth_m = 8.0;         // depth beyond this is invalid (0)
  double depth_time_offset = 0.0;   // depth timestamps = rgb timestamps + this; |offset| < 0.02 s
  int supersampling = 2;            // colour samples per pixel per axis (anti-aliasing), 1..4
  double texel_m = 0.004;           // texture resolution of the room surfaces, metres per texel
  // A static piece of furniture moved once (a chair pushed away): furniture piece `moved_box`
  // (index into the layout's furniture, -1 = none) jumps by moved_box_offset (metres, world
  // frame) at moved_box_time seconds after frame 0, and stays there.
  int moved_box = -1;
  double moved_box_time = 0.0;
  Vec3 moved_box_offset = Vec3::Zero();
  // People close to the camera (issue 13): a pair walking side by side crosses the view
  // close_pass_distance metres in front of the camera (their centre, along its level heading;
  // they keep that distance as the camera moves), entering at close_pass_time seconds after
  // frame 0 from the right, standing nearly still in front for the middle 60 % of
  // close_pass_duration and leaving to the left. close_pass_width metres across, 1.8 m tall,
  // 0.3 m deep: 0.7 m at 0.9 m covers about 75 % of a 640-px image at f = 525. Mover id
  // num_movers + 1. close_pass_time < 0 = none.
  double close_pass_time = -1.0;
  double close_pass_duration = 2.5;  // seconds
  double close_pass_distance = 0.9;  // metres
  double close_pass_width = 0.7;     // metres
  // A blocked sensor: for blocked_frames frames from frame blocked_frame a dark object (a person's
  // back) sits right at the lens, nearer than min_depth_m (so it reads no depth), covering all
  // but a strip at the image's right edge of about 2 % of the pixels. Mover id after the close
  // pair's. blocked_frame < 0 = none.
  int blocked_frame = -1;
  int blocked_frames = 0;
  // The depth sensor's near limit: depth nearer than this is invalid (0). 0 = none.
  double min_depth_m = 0.0;
  // Rolling shutter: seconds from the first to the last image row, in [0, min(0.1, 1 / fps)]
  // (0 = global shutter). Row r of the colour and the depth image is exposed at FrameTime(index) +
  // (r / (height - 1) - 0.5) * readout_time_s, seen from the camera pose and with the movers
  // where they are at that time; the frame's timestamp and ground-truth pose are the middle
  // row's (as RgbdRig::readout_time_s and the settings key Camera.readoutTime expect).
  double readout_time_s = 0.0;

  // Throws esdslam::Error on invalid values.
  void Check() const;

  static CameraIntrinsics DefaultIntrinsics();
};

// Named presets: "static" (arc, no movers, 240 frames), "dynamic" (arc, 3 movers, 240 frames),
// "loop" (closed loop, no movers, 450 frames), "orbit" (1.35 turns around the room centre, 607
// frames, depth noise 0.008 z^2), "corridor" (1.3 turns along a 23 m ring corridor, 781 frames,
// depth and image noise: the loop-closing benchmark), "moved_box" (static arc, 240 frames, the crate
// on the north wall moved 0.9 m west and 0.5 m into the room half way), "occlusion" (arc, 3
// movers, 300 frames: a pair crosses 0.9 m in front of the camera at 3 s and covers 60-80 % of the
// image for about 1.5 s; the sensor is blocked for 4 frames at 7 s; near limit 0.35 m), "rolling"
// (rpy trajectory, no movers, 180 frames at 30 fps, rolling shutter with a 0.025 s readout, depth
// noise 0.002 z^2). Throws Error on an unknown name.
SynthOptions SynthPreset(const std::string& name);

}  // namespace esdslam
