// The real sequences in ../shared: association against a brute-force greedy association of the
// listed timestamps, and image loading (sizes, types, plausible depth).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include <gtest/gtest.h>

#include "io/settings.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

std::string SequenceDir(const std::string& name) { return ::esdslam::testing::TestDataDir() + "/data/" + name; }

std::vector<double> ListedTimes(const std::string& path) {
  std::ifstream in(path);
  std::vector<double> times;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    times.push_back(std::stod(line.substr(0, line.find(' '))));
  }
  return times;
}

// Greedy by smallest |dt| over all pairs, each used once: (rgb time, depth time) sorted by rgb.
std::vector<std::pair<double, double>> BruteForce(const std::vector<double>& rgb, const std::vector<double>& depth) {
  std::vector<std::tuple<double, double, double>> candidates;
  for (double a : rgb) {
    for (double b : depth) {
      if (std::abs(a - b) <= 0.02 + 1e-9) candidates.emplace_back(std::abs(a - b), a, b);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<double> used_a, used_b;
  std::vector<std::pair<double, double>> pairs;
  for (const auto& [dt, a, b] : candidates) {
    if (std::count(used_a.begin(), used_a.end(), a) || std::count(used_b.begin(), used_b.end(), b)) continue;
    used_a.push_back(a);
    used_b.push_back(b);
    pairs.emplace_back(a, b);
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

void CheckSequence(const std::string& name, const std::string& config) {
  const std::string dir = SequenceDir(name);
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "no data at " << dir;
  const TumSequence sequence = TumSequence::Open(dir);
  const auto expected = BruteForce(ListedTimes(dir + "/rgb.txt"), ListedTimes(dir + "/depth.txt"));
  ASSERT_EQ(sequence.frames().size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(sequence.frames()[i].timestamp, expected[i].first);
    EXPECT_EQ(sequence.frames()[i].depth_timestamp, expected[i].second);
  }
  EXPECT_GT(sequence.frames().size(), 100u);
  EXPECT_TRUE(sequence.has_groundtruth());
  EXPECT_GT(ReadTumTrajectory(sequence.groundtruth_path()).size(), 200u);

  const Settings settings = LoadSettings(::esdslam::testing::SourceDir() + "/config/" + config + ".yaml");
  for (const FrameEntry* frame : {&sequence.frames().front(), &sequence.frames().back()}) {
    const RgbdImages images = LoadRgbd(*frame, settings.depth_map_factor);
    EXPECT_EQ(images.bgr.size(), cv::Size(settings.camera.width, settings.camera.height));
    EXPECT_EQ(images.bgr.type(), CV_8UC3);
    EXPECT_EQ(images.depth_m.type(), CV_32F);
    cv::Mat valid = images.depth_m > 0;
    EXPECT_GT(cv::countNonZero(valid), images.depth_m.total() / 3) << frame->depth_path;
    const double mean_depth = cv::mean(images.depth_m, valid)[0];
    EXPECT_GT(mean_depth, 0.3) << frame->depth_path;  // indoor scenes, metres
    EXPECT_LT(mean_depth, 8.0) << frame->depth_path;
  }
}

TEST(TumSequenceSlow, TumFr1Rpy) { CheckSequence("tum_fr1_rpy_dev", "tum_fr1"); }
TEST(TumSequenceSlow, BonnCrowd) { CheckSequence("bonn_crowd_dev", "bonn"); }

}  // namespace
}  // namespace esdslam
