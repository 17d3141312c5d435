#pragma once
// ESD-SLAM's public C++ API: RGB-D SLAM that keeps moving people and objects out of the pose and
// the map. Link the installed package (`find_package(esdslam CONFIG)`, target esdslam::esdslam,
// or pkg-config `esdslam`) and include only this header; everything under src/ is internal.
//
//   esdslam::SystemConfig config;
//   config.settings_file = "config/bonn.yaml";   // ORB-SLAM2-style settings (camera, ORB, ...)
//   esdslam::System slam(config);
//   for (each frame) {
//     esdslam::TrackResult r = slam.Track(bgr, depth_m, timestamp);
//     if (r.has_pose) use(r.world_from_cam);
//   }
//   slam.Shutdown();                              // final poses; outputs written to out_dir
//
// Frames: world = the first keyframe's camera; camera axes x right, y down, z forward (OpenCV);
// poses are world_from_cam (maps camera coordinates to world coordinates), metres.
// Threads: call Track/Shutdown from one thread. The system runs its own threads (segmentation,
// local mapping, loop closing, dense mapping) unless SystemConfig::single_thread is set, in which
// case a run is exactly repeatable. Callbacks run on the thread that calls Track, inside Track.
// Errors: every function throws std::runtime_error (with the file, key or frame at fault) and
// leaves the outputs computed so far on disk when out_dir is set.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace esdslam {

// A rigid transform as a 4x4 homogeneous matrix, row-major (element (r, c) at [4 * r + c]);
// translation in metres.
using Matrix4 = std::array<double, 16>;

enum class TrackingStatus { kNotInitialized, kOk, kLost };
const char* StatusName(TrackingStatus status);  // "NOT_INITIALIZED", "OK", "LOST"

// How the system is built. Every value is checked by System's constructor (Check()).
struct SystemConfig {
  std::string settings_file;  // ORB-SLAM2/3-style YAML settings (the shipped config/*.yaml); or
  std::string settings_text;  // the same as text, used when settings_file is empty
  // Moving-object handling: "none", "semantic" (segmentation network or your labels), "geometry"
  // (multi-view check only) or "full" (both), as `esdslam run --mode`.
  std::string mode = "full";
  // The network labels every K-th frame and the frames between get predicted masks (K >= 1);
  // 0 = the settings' Semantic.segmentEvery. Ignored with label input.
  int segment_every = 0;
  // Labels come from Track's `labels` argument instead of the network (modes semantic, full):
  // class ids into label_classes, which Semantic.dynamicClasses / potentiallyDynamicClasses name.
  bool label_input = false;
  std::vector<std::string> label_classes;  // class id -> name; empty = the PASCAL VOC table
  bool single_thread = false;  // everything on the caller's thread: repeatable results
  bool relocalization = true;
  bool loop_closing = true;
  std::uint32_t seed = 1;      // seeds the RANSACs of relocalization and loop verification
  bool dense = false;          // dense static point cloud and OctoMap, written by Shutdown
  std::string load_map;        // a map file (SaveMap) to start from; empty = a new map
  bool localization = false;   // with load_map: track without adding keyframes
  // Where Shutdown writes trajectory.txt, keyframes.txt (TUM format), timing.csv,
  // settings_used.yaml and with dense the dense outputs; the first three grow as frames are
  // tracked. Empty = nothing written.
  std::string out_dir;
  // >= 0: serve the live viewer (camera image with keypoints and masks, trajectory, map) on
  // http://viewer_address:viewer_port/ while frames are tracked (0 = any free port, ViewerUrl()
  // says which); -1 = off.
  int viewer_port = -1;
  std::string viewer_address = "127.0.0.1";
  void Check() const;  // throws std::runtime_error naming the field
};

// The frame's statistics.
struct FrameStats {
  std::int64_t index = 0;       // 0-based number of the frame
  int keypoints = 0;            // extracted
  int dynamic_keypoints = 0;    // flagged moving (mask or geometry check), kept out of tracking
  int inliers = 0;              // map points matched after pose optimisation
  double mask_ms = 0;           // making the dynamic mask (0 without segmentation)
  double extract_ms = 0;        // ORB extraction
  double track_ms = 0;          // tracking (plus local mapping in single-thread mode)
  long label_age = -1;          // frames since the labels the mask came from; -1 = no labels
};

struct TrackResult {
  TrackingStatus status = TrackingStatus::kNotInitialized;
  bool has_pose = false;
  Matrix4 world_from_cam{};     // valid when has_pose
  bool new_keyframe = false;
  FrameStats stats;
};

struct TimedPose {
  double timestamp = 0;  // seconds
  Matrix4 world_from_cam{};
};

struct KeyFrameInfo {
  long id = 0;
  double timestamp = 0;
  Matrix4 world_from_cam{};
};

struct MapPointInfo {
  long id = 0;
  std::array<double, 3> position_world{};  // metres
  int observations = 0;                     // keyframes that see it
};

// Called on the tracking thread inside Track; keep them short.
struct Callbacks {
  std::function<void(const KeyFrameInfo&)> keyframe_added;
  std::function<void(int loops_closed)> loop_closed;            // total so far
  std::function<void(const TimedPose&)> relocalized;           // the frame that found the map again
};

class System {
 public:
  // Loads the settings, the vocabulary and the network (models are found next to the settings
  // file, the program, the library, $ESDSLAM_DATA_DIR and the install's share/esdslam).
  explicit System(const SystemConfig& config);
  ~System();  // stops every thread; call Shutdown first to get the outputs
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  // bgr: CV_8UC3 (or CV_8UC1 grey) at the settings' Camera.width x height; depth_m: CV_32F metres
  // (0 = invalid) or CV_16U in the settings' DepthMapFactor units; timestamp: seconds, increasing.
  // dynamic_mask: empty or CV_8U, nonzero = moving (joins the system's own mask).
  // labels: CV_8U class ids (required with SystemConfig::label_input, else must be empty).
  // The images are not modified; they are copied when kept.
  TrackResult Track(const cv::Mat& bgr, const cv::Mat& depth_m, double timestamp,
                    const cv::Mat& dynamic_mask = cv::Mat(), const cv::Mat& labels = cv::Mat());

  // Finishes segmentation, local mapping and loop closing (the trajectory is final afterwards)
  // and writes the outputs to out_dir. Idempotent; Track throws afterwards.
  void Shutdown();

  void SetCallbacks(Callbacks callbacks);
  // Writes the map (keyframes, points, descriptors) for SystemConfig::load_map; call after
  // Shutdown for the final map.
  void SaveMap(const std::string& path);

  std::vector<TimedPose> Trajectory() const;   // every frame with a pose, in input order
  std::vector<KeyFrameInfo> KeyFrames() const;  // live keyframes, by id
  std::vector<MapPointInfo> MapPoints() const;  // live map points, by id
  TrackingStatus status() const;
  std::string ViewerUrl() const;  // empty without the viewer
  // The effective settings (every key, flags applied) as YAML text.
  std::string EffectiveSettings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Where the library looks for its models and vocabulary besides the settings' folder (the
// installed share/esdslam, or $ESDSLAM_DATA_DIR when set).
std::string DataDirectory();
const char* Version();

}  // namespace esdslam
