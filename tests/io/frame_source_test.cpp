#include "io/frame_source.h"

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/error.h"
#include "io/test_files.h"

namespace esdslam {
namespace {

using testing::TempDir;

// n frames of 8x6 images at t = 1, 2, ...; frames listed in `corrupt` get a colour file that is
// no PNG.
std::vector<FrameEntry> WriteFrames(const TempDir& dir, int n, const std::vector<int>& corrupt = {}) {
  std::vector<FrameEntry> frames;
  for (int i = 0; i < n; ++i) {
    FrameEntry entry;
    entry.timestamp = entry.depth_timestamp = 1.0 + i;
    entry.rgb_path = dir.Path("rgb" + std::to_string(i) + ".png");
    entry.depth_path = dir.Path("depth" + std::to_string(i) + ".png");
    if (std::find(corrupt.begin(), corrupt.end(), i) != corrupt.end())
      dir.Write("rgb" + std::to_string(i) + ".png", "not a png");
    else
      EXPECT_TRUE(cv::imwrite(entry.rgb_path, cv::Mat(6, 8, CV_8UC3, cv::Scalar::all(90))));
    EXPECT_TRUE(cv::imwrite(entry.depth_path, cv::Mat(6, 8, CV_16UC1, cv::Scalar::all(5000))));
    frames.push_back(entry);
  }
  return frames;
}

std::vector<double> Timestamps(TumFolderSource& source) {
  std::vector<double> stamps;
  while (const auto frame = source.Next()) stamps.push_back(frame->timestamp);
  return stamps;
}

// Regression (issue 14): one corrupt PNG stopped the whole run.
TEST(FrameSourceTest, CorruptFramesAreSkippedAndCounted) {
  TempDir dir;
  TumFolderSource source(WriteFrames(dir, 6, {2, 4}), 5000);
  EXPECT_EQ(Timestamps(source), (std::vector<double>{1, 2, 4, 6}));
  EXPECT_EQ(source.frames_skipped(), 2u);
  EXPECT_EQ(source.frame_count(), 6u);
}

TEST(FrameSourceTest, AFrameDeletedAfterTheListingIsSkipped) {
  TempDir dir;
  std::vector<FrameEntry> frames = WriteFrames(dir, 3);
  std::filesystem::remove(frames[1].depth_path);
  TumFolderSource source(frames, 5000);
  EXPECT_EQ(Timestamps(source), (std::vector<double>{1, 3}));
  EXPECT_EQ(source.frames_skipped(), 1u);
}

TEST(FrameSourceTest, TooManyBadFramesInARowFailNamingTheLastFile) {
  TempDir dir;
  const std::vector<FrameEntry> frames = WriteFrames(dir, 8, {1, 3, 4, 5});
  FolderSourceOptions options;
  options.max_consecutive_bad_frames = 3;
  TumFolderSource source(frames, 5000, options);
  EXPECT_EQ(source.Next()->timestamp, 1);
  EXPECT_EQ(source.Next()->timestamp, 3);  // one bad frame: skipped
  try {
    source.Next();
    FAIL() << "no error after 3 bad frames in a row";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), frames[5].rgb_path);
    EXPECT_NE(std::string(e.what()).find("3 frames in a row"), std::string::npos) << e.what();
  }
}

// Regression (issue 14): images of another size than the settings ran silently with wrong intrinsics.
TEST(FrameSourceTest, AnImageOfAnotherSizeThanTheSettingsIsAnErrorNamingIt) {
  TempDir dir;
  const std::vector<FrameEntry> frames = WriteFrames(dir, 2);
  FolderSourceOptions options;
  options.image_size = cv::Size(640, 480);
  TumFolderSource source(frames, 5000, options);
  try {
    source.Next();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), frames[0].rgb_path);
    EXPECT_NE(std::string(e.what()).find("8x6"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("Camera.width/Camera.height are 640x480"), std::string::npos) << e.what();
  }
}

TEST(FrameSourceTest, OptionsAreChecked) {
  FolderSourceOptions options;
  options.max_consecutive_bad_frames = 0;
  EXPECT_THROW(options.Check(), Error);
  EXPECT_THROW(TumFolderSource({}, 5000, options), Error);
}

}  // namespace
}  // namespace esdslam
