#include "io/tum_sequence.h"

#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/error.h"
#include "io/test_files.h"

namespace esdslam {
namespace {

using testing::TempDir;

void WriteColour(const TempDir& dir, const std::string& relative, int type = CV_8UC3) {
  std::filesystem::create_directories(std::filesystem::path(dir.Path(relative)).parent_path());
  ASSERT_TRUE(cv::imwrite(dir.Path(relative), cv::Mat(6, 8, type, cv::Scalar::all(100))));
}

void WriteDepth(const TempDir& dir, const std::string& relative, uint16_t value, int type = CV_16UC1) {
  std::filesystem::create_directories(std::filesystem::path(dir.Path(relative)).parent_path());
  cv::Mat depth(6, 8, type, cv::Scalar::all(value));
  if (type == CV_16UC1) depth.at<uint16_t>(0, 0) = 0;  // an invalid pixel
  ASSERT_TRUE(cv::imwrite(dir.Path(relative), depth));
}

// A sequence folder: rgb at 1.00 1.10 1.20 1.30, depth at +0.005, +0.02 (boundary), +0.03 (too
// far), +0.001. The image of depth 1.301 is not written (listed but missing).
void WriteSequence(const TempDir& dir) {
  dir.Write("rgb.txt", "# color images\n# timestamp filename\n1.00 rgb/a.png\n1.10 rgb/b.png\n"
                       "1.20 rgb/c.png\n1.30 rgb/d.png\n");
  dir.Write("depth.txt", "# depth\n1.005 depth/a.png\n1.12 depth/b.png\n1.23 depth/c.png\n1.301 depth/d.png\n");
  for (const char* name : {"a", "b", "c", "d"}) WriteColour(dir, std::string("rgb/") + name + ".png");
  for (const char* name : {"a", "b", "c"}) WriteDepth(dir, std::string("depth/") + name + ".png", 5000);
}

void ExpectOpenError(const std::string& dir, const AssociationOptions& options, const std::string& file, int line,
                     const std::string& fragment) {
  try {
    TumSequence::Open(dir, options);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(TumSequence, AssociatesWithinMaxDifferenceAndSkipsMissingFiles) {
  TempDir dir;
  WriteSequence(dir);
  const TumSequence sequence = TumSequence::Open(dir.Path());
  ASSERT_EQ(sequence.frames().size(), 2u);  // 1.00 (dt .005), 1.10 (dt .02); 1.20 too far; 1.30 missing
  EXPECT_DOUBLE_EQ(sequence.frames()[0].timestamp, 1.00);
  EXPECT_DOUBLE_EQ(sequence.frames()[0].depth_timestamp, 1.005);
  EXPECT_EQ(sequence.frames()[0].rgb_path, dir.Path("rgb/a.png"));
  EXPECT_EQ(sequence.frames()[0].depth_path, dir.Path("depth/a.png"));
  EXPECT_DOUBLE_EQ(sequence.frames()[1].timestamp, 1.10);
  EXPECT_DOUBLE_EQ(sequence.frames()[1].depth_timestamp, 1.12);
  ASSERT_EQ(sequence.skipped_files().size(), 1u);
  EXPECT_EQ(sequence.skipped_files()[0], dir.Path("depth/d.png"));
  EXPECT_FALSE(sequence.has_groundtruth());
  dir.Write("groundtruth.txt", "1 0 0 0 0 0 0 1\n");
  EXPECT_TRUE(sequence.has_groundtruth());
  EXPECT_EQ(sequence.groundtruth_path(), dir.Path("groundtruth.txt"));
}

TEST(TumSequence, LargerMaxDifferenceAcceptsMore) {
  TempDir dir;
  WriteSequence(dir);
  AssociationOptions options;
  options.max_time_difference = 0.031;
  EXPECT_EQ(TumSequence::Open(dir.Path(), options).frames().size(), 3u);
}

TEST(TumSequence, ReadsAssociationFile) {
  TempDir dir;
  WriteSequence(dir);
  AssociationOptions options;
  options.association_file =
      dir.Write("assoc.txt", "1.20 rgb/c.png 1.23 depth/c.png\n1.30 rgb/d.png 1.301 depth/d.png\n");
  const TumSequence sequence = TumSequence::Open(dir.Path(), options);
  ASSERT_EQ(sequence.frames().size(), 1u);  // d skipped: its depth image is missing
  EXPECT_DOUBLE_EQ(sequence.frames()[0].timestamp, 1.20);
  EXPECT_EQ(sequence.frames()[0].depth_path, dir.Path("depth/c.png"));
}

TEST(TumSequence, BadInputsNameFileAndLine) {
  TempDir dir;
  WriteSequence(dir);
  ExpectOpenError(dir.Path("missing_folder"), {}, dir.Path("missing_folder"), 0, "folder not found");
  AssociationOptions assoc;
  assoc.association_file = dir.Write("assoc.txt", "1.0 rgb/a.png 1.005\n");
  ExpectOpenError(dir.Path(), assoc, assoc.association_file, 1, "expected 4 fields");
  assoc.association_file = dir.Path("none.txt");
  ExpectOpenError(dir.Path(), assoc, assoc.association_file, 0, "not found");
  dir.Write("rgb.txt", "1.00 rgb/a.png\nx1.10 rgb/b.png\n");
  ExpectOpenError(dir.Path(), {}, dir.Path("rgb.txt"), 2, "timestamp");
  dir.Write("rgb.txt", "1.00 rgb/a.png\n1.10\n");
  ExpectOpenError(dir.Path(), {}, dir.Path("rgb.txt"), 2, "expected 2 fields");
  dir.Write("rgb.txt", "1.10 rgb/a.png\n1.00 rgb/b.png\n");
  ExpectOpenError(dir.Path(), {}, dir.Path("rgb.txt"), 2, "not sorted");
  dir.Write("rgb.txt", "1.00 rgb/a.png\n1.00 rgb/b.png\n");
  ExpectOpenError(dir.Path(), {}, dir.Path("rgb.txt"), 2, "duplicate");
  std::filesystem::remove(dir.Path("depth.txt"));
  dir.Write("rgb.txt", "1.00 rgb/a.png\n");
  ExpectOpenError(dir.Path(), {}, dir.Path("depth.txt"), 0, "not found");
}

TEST(TumSequence, EmptySequenceIsAnError) {
  TempDir dir;
  WriteSequence(dir);
  dir.Write("depth.txt", "5.0 depth/a.png\n");  // nothing within 0.02 s
  ExpectOpenError(dir.Path(), {}, dir.Path(), 0, "empty sequence");
  dir.Write("depth.txt", "1.30 depth/d.png\n");  // associates, but the file is missing
  ExpectOpenError(dir.Path(), {}, dir.Path(), 0, "empty sequence");
}

TEST(TumSequence, RejectsNonPositiveMaxDifference) {
  AssociationOptions options;
  options.max_time_difference = 0;
  EXPECT_THROW(options.Check(), Error);
}

TEST(LoadRgbd, ConvertsDepthToMetres) {
  TempDir dir;
  WriteSequence(dir);
  const TumSequence sequence = TumSequence::Open(dir.Path());
  const RgbdImages images = LoadRgbd(sequence.frames()[0], 5000.0);
  EXPECT_EQ(images.bgr.type(), CV_8UC3);
  EXPECT_EQ(images.depth_m.type(), CV_32F);
  EXPECT_EQ(images.bgr.size(), cv::Size(8, 6));
  EXPECT_FLOAT_EQ(images.depth_m.at<float>(1, 1), 1.0f);  // 5000 / 5000
  EXPECT_FLOAT_EQ(images.depth_m.at<float>(0, 0), 0.0f);  // invalid stays 0
  EXPECT_FLOAT_EQ(LoadRgbd(sequence.frames()[0], 1000.0).depth_m.at<float>(1, 1), 5.0f);
}

TEST(LoadRgbd, GreyColourImageBecomesThreeChannels) {
  TempDir dir;
  WriteColour(dir, "g.png", CV_8UC1);
  WriteDepth(dir, "d.png", 100);
  const RgbdImages images = LoadRgbd({0, dir.Path("g.png"), 0, dir.Path("d.png")}, 5000);
  EXPECT_EQ(images.bgr.type(), CV_8UC3);
}

void ExpectLoadError(const FrameEntry& frame, const std::string& file, const std::string& fragment) {
  try {
    LoadRgbd(frame, 5000);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(LoadRgbd, BadImagesNameTheFile) {
  TempDir dir;
  WriteColour(dir, "c.png");
  WriteDepth(dir, "d.png", 100);
  WriteDepth(dir, "d8.png", 100, CV_8UC1);
  dir.Write("broken.png", "not a png");
  std::filesystem::create_directories(dir.Path("small"));
  ASSERT_TRUE(cv::imwrite(dir.Path("small/d.png"), cv::Mat(3, 4, CV_16UC1, cv::Scalar(1))));
  ExpectLoadError({0, dir.Path("none.png"), 0, dir.Path("d.png")}, dir.Path("none.png"), "not found");
  ExpectLoadError({0, dir.Path("c.png"), 0, dir.Path("none.png")}, dir.Path("none.png"), "not found");
  ExpectLoadError({0, dir.Path("broken.png"), 0, dir.Path("d.png")}, dir.Path("broken.png"), "cannot decode");
  ExpectLoadError({0, dir.Path("c.png"), 0, dir.Path("broken.png")}, dir.Path("broken.png"), "cannot decode");
  ExpectLoadError({0, dir.Path("c.png"), 0, dir.Path("d8.png")}, dir.Path("d8.png"), "16-bit");
  ExpectLoadError({0, dir.Path("d.png"), 0, dir.Path("d.png")}, dir.Path("d.png"), "8-bit");
  ExpectLoadError({0, dir.Path("c.png"), 0, dir.Path("small/d.png")}, dir.Path("small/d.png"), "differs");
}

}  // namespace
}  // namespace esdslam
