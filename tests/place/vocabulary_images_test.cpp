#include "place/vocabulary_images.h"

#include <filesystem>
#include <fstream>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "support/temp_path.h"

namespace esdslam {
namespace {
namespace fs = std::filesystem;

class VocabularyImagesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = testing::TestTempPath("loop_images_test");
    fs::remove_all(root_);
    fs::create_directories(root_ / "plain");
    fs::create_directories(root_ / "tum" / "rgb");
    cv::Mat noise(240, 320, CV_8U);
    cv::RNG rng(1);
    rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
    cv::GaussianBlur(noise, noise, cv::Size(3, 3), 0);
    for (int i = 0; i < 6; ++i) cv::imwrite((root_ / "plain" / ("img" + std::to_string(i) + ".png")).string(), noise);
    for (int i = 0; i < 4; ++i) cv::imwrite((root_ / "tum" / "rgb" / (std::to_string(i) + ".png")).string(), noise);
    std::ofstream((root_ / "plain" / "notes.txt").string()) << "not an image";
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
};

TEST_F(VocabularyImagesTest, ListsImagesInFoldersAndRgbSubfolders) {
  const std::vector<std::string> all = ListTrainingImages({(root_ / "plain").string(), (root_ / "tum").string()});
  ASSERT_EQ(all.size(), 10u);
  EXPECT_EQ(fs::path(all.front()).filename(), "img0.png");
  EXPECT_EQ(fs::path(all.back()).parent_path().filename(), "rgb");
  const std::vector<std::string> some = ListTrainingImages({(root_ / "plain").string(), (root_ / "tum").string()}, 5);
  ASSERT_EQ(some.size(), 5u);
  EXPECT_EQ(some[0], all[0]);
  EXPECT_EQ(some[1], all[2]);  // evenly spaced
  EXPECT_THROW(ListTrainingImages({(root_ / "missing").string()}), Error);
}

TEST_F(VocabularyImagesTest, ExtractsOrbDescriptorsAndRejectsUnreadableImages) {
  OrbOptions options;
  options.num_features = 300;
  const std::vector<std::string> images = ListTrainingImages({(root_ / "tum").string()});
  const std::vector<cv::Mat> descriptors = ExtractTrainingDescriptors(images, options);
  ASSERT_EQ(descriptors.size(), 4u);
  EXPECT_GT(descriptors[0].rows, 200);
  EXPECT_EQ(descriptors[0].cols, 32);
  EXPECT_EQ(descriptors[0].type(), CV_8U);
  EXPECT_THROW(ExtractTrainingDescriptors({(root_ / "plain" / "notes.txt").string()}, options), InputError);
}

}  // namespace
}  // namespace esdslam
