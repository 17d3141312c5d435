#include "semantic/onnx_segmenter.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <unistd.h>

#include "common/error.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {
namespace fs = std::filesystem;

std::string ShippedModel() { return ::esdslam::testing::SourceDir() + "/models/espnetv2_s2.0_voc_256x192.onnx"; }

TEST(OnnxSegmenter, MissingModelIsAClearError) {
  OnnxSegmenterOptions o;
  o.model_path = "/nonexistent/model.onnx";
  try {
    OnnxSegmenter segmenter(o);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not found"), std::string::npos) << e.what();
  }
}

TEST(OnnxSegmenter, CorruptModelIsAClearError) {
  const fs::path path = fs::temp_directory_path() / ("esdslam_bad_model_" + std::to_string(::getpid()) + ".onnx");
  std::ofstream(path) << "this is not a protobuf";
  OnnxSegmenterOptions o;
  o.model_path = path.string();
  EXPECT_THROW(OnnxSegmenter{o}, Error);
  fs::remove(path);
}

TEST(OnnxSegmenter, WrongInputSizeForTheModelIsAnError) {
  OnnxSegmenterOptions o;
  o.model_path = ShippedModel();
  o.input_width = 384;  // the model was exported for 256x192
  o.input_height = 288;
  EXPECT_THROW(OnnxSegmenter{o}, Error);
}

TEST(OnnxSegmenter, OptionsCheck) {
  OnnxSegmenterOptions o;
  o.model_path = "x.onnx";
  EXPECT_NO_THROW(o.Check());
  o.input_width = 250;
  EXPECT_THROW(o.Check(), Error);
  o.input_width = 256;
  o.std_rgb[1] = 0.0f;
  EXPECT_THROW(o.Check(), Error);
}

TEST(OnnxSegmenter, ShippedModelLabelsAtImageResolution) {
  OnnxSegmenterOptions o;
  o.model_path = ShippedModel();
  o.input_width = 256;
  o.input_height = 192;
  OnnxSegmenter segmenter(o);
  const cv::Mat grey(120, 200, CV_8UC3, cv::Scalar::all(128));  // a blank wall: background
  const SegmentationResult r = segmenter.Segment(grey, 0.0);
  ASSERT_EQ(r.labels.type(), CV_8UC1);
  ASSERT_EQ(r.labels.size(), grey.size());
  ASSERT_EQ(r.person_probability.type(), CV_32FC1);
  ASSERT_EQ(r.person_probability.size(), grey.size());
  EXPECT_GT(cv::countNonZero(r.labels == 0), 0.9 * static_cast<double>(r.labels.total()));
  double max_person = 0.0;
  cv::minMaxLoc(r.person_probability, nullptr, &max_person);
  EXPECT_LT(max_person, 0.5);
  EXPECT_GT(r.segment_ms, 0.0);
}

TEST(OnnxSegmenter, ShippedModelsFinalResizeIsDoneOutsideTheNetwork) {
  // The load-time check found that UpsampleAlignCorners gives the network's own final Resize.
  OnnxSegmenterOptions o;
  o.model_path = ShippedModel();
  o.input_width = 256;
  o.input_height = 192;
  EXPECT_TRUE(OnnxSegmenter(o).upsamples_scores_itself());
}

TEST(ArgmaxAndSoftmax, KnownAnswers) {
  std::vector<cv::Mat> scores{cv::Mat(1, 3, CV_32F), cv::Mat(1, 3, CV_32F)};
  scores[0].at<float>(0) = 1.0f, scores[1].at<float>(0) = 0.0f;
  scores[0].at<float>(1) = 0.0f, scores[1].at<float>(1) = 2.0f;
  scores[0].at<float>(2) = 1.0f, scores[1].at<float>(2) = 1.0f;  // tie -> lower id
  const cv::Mat labels = ArgmaxLabels(scores);
  EXPECT_EQ(labels.at<uchar>(0), 0);
  EXPECT_EQ(labels.at<uchar>(1), 1);
  EXPECT_EQ(labels.at<uchar>(2), 0);
  const cv::Mat p = SoftmaxProbability(scores, 1);
  EXPECT_NEAR(p.at<float>(0), 1.0 / (1.0 + std::exp(1.0)), 1e-6);
  EXPECT_NEAR(p.at<float>(1), 1.0 / (1.0 + std::exp(-2.0)), 1e-6);
  EXPECT_NEAR(p.at<float>(2), 0.5, 1e-6);
}

}  // namespace
}  // namespace esdslam
