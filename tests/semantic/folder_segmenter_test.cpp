#include "semantic/folder_segmenter.h"

#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <unistd.h>

#include "common/error.h"

namespace esdslam {
namespace {
namespace fs = std::filesystem;

class FolderSegmenterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("esdslam_folder_seg_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    WriteMask("1548339828.254410", 7);
    WriteMask("1548339828.287650", 15);
    cv::imwrite((dir_ / "notes.png").string(), cv::Mat(4, 4, CV_8UC1, cv::Scalar(1)));  // not a timestamp
  }
  void TearDown() override { fs::remove_all(dir_); }
  void WriteMask(const std::string& stem, int value) {
    cv::Mat labels(4, 6, CV_8UC1, cv::Scalar(value));
    labels.at<uchar>(0, 0) = 0;
    ASSERT_TRUE(cv::imwrite((dir_ / (stem + ".png")).string(), labels));
  }
  FolderSegmenterOptions Options() const {
    FolderSegmenterOptions o;
    o.folder = dir_.string();
    o.tolerance_s = 0.01;
    return o;
  }
  fs::path dir_;
  cv::Mat frame_{4, 6, CV_8UC3, cv::Scalar(1, 2, 3)};
};

TEST_F(FolderSegmenterTest, PicksTheNearestMaskWithinTolerance) {
  FolderSegmenter segmenter(Options());
  EXPECT_EQ(segmenter.NumMasks(), 2u);
  const SegmentationResult a = segmenter.Segment(frame_, 1548339828.258);  // 3.6 ms from the first
  EXPECT_EQ(a.labels.at<uchar>(1, 1), 7);
  EXPECT_EQ(a.labels.at<uchar>(0, 0), 0);
  const SegmentationResult b = segmenter.Segment(frame_, 1548339828.280);  // nearer the second
  EXPECT_EQ(b.labels.at<uchar>(1, 1), 15);
  EXPECT_TRUE(b.person_probability.empty());
}

TEST_F(FolderSegmenterTest, MissingMaskIsAnErrorNamingTheTimestamp) {
  FolderSegmenter segmenter(Options());
  try {
    segmenter.Segment(frame_, 1548339829.0);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("1548339829.000000"), std::string::npos) << e.what();
  }
}

TEST_F(FolderSegmenterTest, AllowMissingGivesBackground) {
  FolderSegmenterOptions o = Options();
  o.allow_missing = true;
  FolderSegmenter segmenter(o);
  const SegmentationResult r = segmenter.Segment(frame_, 1548339829.0);
  ASSERT_EQ(r.labels.size(), frame_.size());
  EXPECT_EQ(cv::countNonZero(r.labels), 0);
}

TEST_F(FolderSegmenterTest, MaskOfAnotherSizeIsResizedNearest) {
  FolderSegmenter segmenter(Options());
  const cv::Mat big(8, 12, CV_8UC3, cv::Scalar::all(0));
  const SegmentationResult r = segmenter.Segment(big, 1548339828.2544);
  ASSERT_EQ(r.labels.size(), big.size());
  EXPECT_EQ(r.labels.at<uchar>(0, 0), 0);
  EXPECT_EQ(r.labels.at<uchar>(1, 1), 0);  // top-left 2x2 block comes from the one 0 pixel
  EXPECT_EQ(r.labels.at<uchar>(5, 7), 7);
}

TEST_F(FolderSegmenterTest, MissingFolderOrColourMaskIsAnError) {
  FolderSegmenterOptions o = Options();
  o.folder = (dir_ / "nope").string();
  EXPECT_THROW(FolderSegmenter{o}, Error);
  cv::imwrite((dir_ / "1548339830.0.png").string(), cv::Mat(4, 6, CV_8UC3, cv::Scalar::all(9)));
  FolderSegmenter segmenter(Options());
  EXPECT_THROW(segmenter.Segment(frame_, 1548339830.0), Error);
}

}  // namespace
}  // namespace esdslam
