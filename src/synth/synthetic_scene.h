#pragma once
// Deterministic synthetic RGB-D scenes with known camera motion and moving people.
//
//   SyntheticScene scene(SynthPreset("dynamic"));
//   SynthFrame frame = scene.RenderFrame(10);   // colour, depth, ground-truth mover mask
//
// The scene (see synth/synth_paths.h for the world frame) is a textured room with static
// furniture and `num_movers` textured person-sized boxes walking through it. Images are ray
// cast per pixel: colour averages supersampling^2 rays per pixel (anti-aliasing), depth, mask
// and surface id come from the ray through the pixel centre, so depth is exact (no mixed
// pixels at edges) apart from the optional noise. With a rolling shutter
// (SynthOptions::readout_time_s) each row is ray cast from the camera and mover poses at its own
// exposure time.

#include <cstdint>
#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "io/trajectory_io.h"
#include "synth/synth_options.h"
#include "synth/synth_paths.h"
#include "synth/textured_box.h"

namespace esdslam {

struct SynthFrame {
  int index = -1;               // frame number, -1 for a free render
  double timestamp = 0;         // seconds (rgb)
  double depth_timestamp = 0;   // seconds
  Rigid3 world_from_cam;
  cv::Mat bgr;          // CV_8UC3
  cv::Mat depth_m;      // CV_32F, metres along the optical axis; 0 = invalid (beyond max_depth_m)
  cv::Mat mover_mask;   // CV_8U: 0 = static scene, k = mover k (1-based)
  cv::Mat surface_id;   // CV_32S: 6 * box index + face of the surface seen at the pixel centre
};

struct SynthRayHit {
  double t = 0;        // ray parameter: point = origin + t * dir
  int box = -1;        // index into boxes(); -1 = nothing hit
  int face = -1;
  int object_id = 0;   // 0 = static, k = mover k
};

class SyntheticScene {
 public:
  // Builds the room, furniture, movers and their textures (about 0.2 s). Calls options.Check().
  explicit SyntheticScene(const SynthOptions& options);

  const SynthOptions& options() const { return options_; }
  const PinholeCamera& camera() const { return camera_; }
  int num_frames() const { return options_.num_frames; }
  // Moving objects: the walking people of num_movers lanes, then the close pair and the lens
  // blocker when the options ask for them (mover ids 1..num_movers() in that order).
  int num_movers() const { return static_cast<int>(boxes_.size()) - first_mover_box_; }

  double FrameTime(int index) const { return index / options_.fps; }  // seconds since frame 0
  double Timestamp(int index) const { return options_.first_timestamp + FrameTime(index); }
  double DepthTimestamp(int index) const { return Timestamp(index) + options_.depth_time_offset; }
  Rigid3 WorldFromCam(int index) const { return CameraPoseAt(options_, FrameTime(index)); }
  std::vector<StampedPose> GroundTruth() const;  // one pose per frame, rgb timestamps

  const std::vector<TexturedBox>& boxes() const { return boxes_; }
  // Pose of box `box` at `time` (seconds since frame 0); static boxes ignore time, except the
  // moved one (SynthOptions::moved_box).
  Rigid3 WorldFromBox(int box, double time) const;
  // Index into boxes() of mover k (1-based).
  int MoverBox(int mover_id) const { return first_mover_box_ + mover_id - 1; }

  // Frame `index` with its ground-truth pose (the middle row's), time and noise seed; with a
  // rolling shutter (options().readout_time_s > 0) rendered by RenderRolling along the trajectory.
  SynthFrame RenderFrame(int index) const;
  // Renders any pose at any time with a global shutter (every row at `time`, seconds since frame
  // 0). Depth noise (if enabled) is drawn from `noise_seed`.
  SynthFrame Render(const Rigid3& world_from_cam, double time, std::uint32_t noise_seed) const;
  // Rolling shutter: renders colour and depth row by row, row v as Render would at RowTime(time,
  // v) from world_from_cam_at(RowTime(time, v)) with the movers at that time. The frame's pose is
  // world_from_cam_at(time) (the middle row's). Readout 0: every row at `time`.
  SynthFrame RenderRolling(const std::function<Rigid3(double)>& world_from_cam_at, double time,
                           std::uint32_t noise_seed) const;
  // Exposure time of image row `row` of a frame at `time` (seconds since frame 0):
  // time + (row / (height - 1) - 0.5) * options().readout_time_s.
  double RowTime(double time, int row) const;
  // Nearest surface along the world ray origin + t * dir (t > 0) at `time`.
  SynthRayHit CastRay(const Vec3& origin, const Vec3& dir, double time) const;

 private:
  void BuildStaticScene(std::mt19937& rng);
  void BuildMovers(std::mt19937& rng);
  // Adds a person-like box (shirt and trousers textures) with the next mover id.
  void AddPersonBox(const Vec3& half_size, std::mt19937& rng);
  // Images of the camera's size (contents undefined), pose and timestamps set.
  SynthFrame AllocateFrame(const Rigid3& world_from_cam, double time) const;

  SynthOptions options_;
  PinholeCamera camera_;
  std::vector<TexturedBox> boxes_;
  std::vector<Vec3> static_centres_;  // centres of the static boxes (axis-aligned)
  int first_mover_box_ = 0;
  std::vector<MoverPath> mover_paths_;
  int close_pass_box_ = -1;  // index into boxes_, -1 = none
  int blocker_box_ = -1;
};

}  // namespace esdslam
