#pragma once
// Options of the browser viewer (`esdslam run --viewer`, `esdslam view`): where it listens, what
// it sends and how much of it. Every bound keeps the data a browser gets per second small, so
// that encoding stays a small share of one core (the viewer must cost <= 5 % of tracking).

#include <cstddef>
#include <string>

namespace esdslam {

struct ViewerOptions {
  std::string address = "127.0.0.1";  // bind address; only localhost by default
  int port = 8080;                    // TCP port; 0 = any free port (ViewerServer::port says which)
  // The page and its scripts: index.html, viewer.js and node_modules/three (npm ci, tools/web).
  std::string web_dir = DefaultWebDir();
  double image_scale = 0.5;      // colour frame scaled by this before JPEG encoding (1 = full size)
  int jpeg_quality = 70;         // 1..100
  int max_keypoints = 2000;      // keypoints sent per frame (evenly strided beyond that)
  int max_map_points = 20000;    // static map points per map update
  int max_dynamic_points = 5000; // removed (dynamic) keypoints kept, back-projected, newest win
  int max_dense_points = 30000;  // dense-map points per map update (with --dense)
  int max_trajectory = 5000;     // camera positions per map update
  double frame_interval_ms = 100;  // at most one frame event per this many ms (10 Hz)
  double map_interval_ms = 1000;  // at most one map update per this many ms
  // The dense cloud is rebuilt (DenseMapper::CurrentCloud: outlier filter over the whole map,
  // 0.1-1 s of CPU) at most this often, and only when the dense map has new keyframes.
  double dense_interval_ms = 10000;
  std::size_t queue_capacity = 1;  // frames waiting for the viewer thread; a newer one replaces the oldest

  // Throws Error naming the option of a value outside its range.
  void Check() const;
  // The page's folder, tools/web, found as data (common/data_files.h): the source tree beside a
  // build, or share/esdslam/tools/web of an install.
  static std::string DefaultWebDir();
};

}  // namespace esdslam
