// Tracks a TUM-layout RGB-D folder (rgb.txt, depth.txt) with the installed ESD-SLAM library.
// Usage: track_tum SETTINGS.yaml SEQUENCE_DIR OUT_DIR [--single-thread]
// Writes OUT_DIR/trajectory.txt (TUM format) and the run's other outputs.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <esdslam/esdslam.h>
#include <opencv2/imgcodecs.hpp>

struct Entry { double t; std::string file; };

static std::vector<Entry> ReadList(const std::string& path) {
  std::vector<Entry> entries;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    Entry e;
    if (line.empty() || line[0] == '#' || !(words >> e.t >> e.file)) continue;
    entries.push_back(e);
  }
  return entries;
}

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s SETTINGS SEQUENCE_DIR OUT_DIR [--single-thread]\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[2];
  esdslam::SystemConfig config;
  config.settings_file = argv[1];
  config.out_dir = argv[3];
  config.single_thread = argc > 4 && std::string(argv[4]) == "--single-thread";
  try {
    esdslam::System slam(config);
    const std::vector<Entry> rgb = ReadList(dir + "/rgb.txt"), depth = ReadList(dir + "/depth.txt");
    std::size_t d = 0, tracked = 0;
    for (const Entry& frame : rgb) {
      while (d + 1 < depth.size() && std::abs(depth[d + 1].t - frame.t) < std::abs(depth[d].t - frame.t)) ++d;
      if (depth.empty() || std::abs(depth[d].t - frame.t) > 0.02) continue;  // no depth for this image
      const cv::Mat bgr = cv::imread(dir + "/" + frame.file, cv::IMREAD_COLOR);
      const cv::Mat raw_depth = cv::imread(dir + "/" + depth[d].file, cv::IMREAD_UNCHANGED);  // CV_16U
      if (bgr.empty() || raw_depth.empty()) throw std::runtime_error("cannot read " + frame.file);
      const esdslam::TrackResult result = slam.Track(bgr, raw_depth, frame.t);
      tracked += result.has_pose;
    }
    slam.Shutdown();
    std::printf("frames %zu tracked %zu keyframes %zu map points %zu\n", rgb.size(), tracked,
                slam.KeyFrames().size(), slam.MapPoints().size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "track_tum: %s\n", e.what());
    return 1;
  }
  return 0;
}
