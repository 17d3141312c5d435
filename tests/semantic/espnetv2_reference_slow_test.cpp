// The shipped ONNX models on OpenCV DNN against the outputs of the original network
// (../shared/models/espnetv2/reference, 384x384 input), and the committed models against a
// fresh export by tools/espnetv2/export.py (skipped without python3-torch).
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <unistd.h>

#include "semantic/onnx_segmenter.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {
namespace fs = std::filesystem;

const fs::path kReferenceDir = fs::path(::esdslam::testing::TestDataDir()) / "models" / "espnetv2" / "reference";
const fs::path kModelDir = fs::path(::esdslam::testing::SourceDir()) / "models";

OnnxSegmenter MakeSegmenter(const fs::path& model, int width, int height) {
  OnnxSegmenterOptions o;
  o.model_path = model.string();
  o.input_width = width;
  o.input_height = height;
  return OnnxSegmenter(o);
}

TEST(EspNetV2Reference, LabelsAndPersonProbabilityMatchTheOriginalNetwork) {
  if (!fs::is_directory(kReferenceDir)) GTEST_SKIP() << "no reference data at " << kReferenceDir;
  OnnxSegmenter segmenter = MakeSegmenter(kModelDir / "espnetv2_s2.0_voc_384x384.onnx", 384, 384);
  int frames = 0;
  for (const auto& entry : fs::directory_iterator(kReferenceDir)) {
    const std::string name = entry.path().filename().string();
    const std::string suffix = ".labels.png";
    if (name.size() <= suffix.size() || name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) continue;
    const std::string stem = (kReferenceDir / name.substr(0, name.size() - suffix.size())).string();
    const cv::Mat bgr = cv::imread(stem + ".png", cv::IMREAD_COLOR);
    const cv::Mat ref_labels = cv::imread(stem + ".labels.png", cv::IMREAD_UNCHANGED);
    const cv::Mat ref_person = cv::imread(stem + ".person_prob.png", cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(bgr.empty() || ref_labels.empty() || ref_person.empty()) << stem;

    const std::vector<cv::Mat> scores = segmenter.Scores(bgr);
    const cv::Mat labels = ArgmaxLabels(scores);
    const double label_agreement = cv::countNonZero(labels == ref_labels) / static_cast<double>(labels.total());
    cv::Mat person_grey, ref_person_f, diff;
    SoftmaxProbability(scores, kVocPersonClass).convertTo(person_grey, CV_32F, 255.0);
    ref_person.convertTo(ref_person_f, CV_32F);
    cv::absdiff(person_grey, ref_person_f, diff);
    const double person_close = cv::countNonZero(diff <= 3.0) / static_cast<double>(diff.total());
    std::printf("%s: labels %.3f%%, person prob within 3 grey levels %.3f%%\n", name.c_str(),
                100.0 * label_agreement, 100.0 * person_close);
    EXPECT_GE(label_agreement, 0.995) << stem;
    EXPECT_GE(person_close, 0.99) << stem;
    ++frames;
  }
  EXPECT_EQ(frames, 6);
}

// Segment() upsamples only the classes present at network resolution; compare with upsampling
// all 21 score planes at full 640x480 resolution.
TEST(EspNetV2Reference, UpsamplingPresentClassesMatchesUpsamplingAll) {
  if (!fs::is_directory(kReferenceDir)) GTEST_SKIP() << "no reference data at " << kReferenceDir;
  OnnxSegmenter segmenter = MakeSegmenter(kModelDir / "espnetv2_s2.0_voc_384x288.onnx", 384, 288);
  for (const char* name : {"bonn_crowd_1548339830.60015.png", "bonn_crowd_1548339839.64913.png"}) {
    const cv::Mat bgr = cv::imread((kReferenceDir / name).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(bgr.empty());
    std::vector<cv::Mat> scores = segmenter.Scores(bgr);
    for (auto& s : scores) cv::resize(s, s, bgr.size(), 0, 0, cv::INTER_LINEAR);
    const cv::Mat all = ArgmaxLabels(scores);
    const cv::Mat labels = segmenter.Segment(bgr, 0.0).labels;
    ASSERT_EQ(labels.size(), bgr.size());
    const double agreement = cv::countNonZero(labels == all) / static_cast<double>(all.total());
    EXPECT_GE(agreement, 0.9999) << name;
    EXPECT_GT(cv::countNonZero(labels == kVocPersonClass), 0.05 * static_cast<double>(labels.total())) << name;
  }
}

TEST(EspNetV2Reference, CommittedModelsEqualAFreshExport) {
  if (std::system("/usr/bin/python3 -c 'import torch, onnx' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "python3-torch / python3-onnx not installed";
  const fs::path weights = fs::path(::esdslam::testing::TestDataDir()) / "models" / "espnetv2";
  if (!fs::is_directory(weights)) GTEST_SKIP() << "no weights at " << weights;
  const fs::path out = fs::temp_directory_path() / ("esdslam_export_" + std::to_string(::getpid()));
  const std::string command = "PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 " + ::esdslam::testing::SourceDir() +
                              "/tools/espnetv2/export.py --no-reference-check --weights-dir " +
                              weights.string() + " --out " + out.string() + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const cv::Mat bgr = cv::imread((kReferenceDir / "bonn_crowd_1548339834.62159.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(bgr.empty());
  const int sizes[][2] = {{256, 192}, {384, 288}, {384, 384}};
  for (const auto& size : sizes) {
    const std::string file = "espnetv2_s2.0_voc_" + std::to_string(size[0]) + "x" + std::to_string(size[1]) + ".onnx";
    OnnxSegmenter committed = MakeSegmenter(kModelDir / file, size[0], size[1]);
    OnnxSegmenter fresh = MakeSegmenter(out / file, size[0], size[1]);
    const std::vector<cv::Mat> a = committed.Scores(bgr), b = fresh.Scores(bgr);
    double worst = 0.0;
    for (std::size_t c = 0; c < a.size(); ++c) worst = std::max(worst, cv::norm(a[c], b[c], cv::NORM_INF));
    EXPECT_LT(worst, 1e-3) << file;
  }
  fs::remove_all(out);
}

}  // namespace
}  // namespace esdslam

namespace esdslam {
namespace {

// `esdslam segment` end to end (skipped when the program has not been built).
TEST(EsdslamSegmentCommand, WritesFullResolutionLabelsAndFailsOnABadModel) {
  const fs::path program = fs::path(::esdslam::testing::BinaryDir()) / "esdslam";
  if (!fs::exists(program)) GTEST_SKIP() << "build the esdslam target first";
  if (!fs::is_directory(kReferenceDir)) GTEST_SKIP() << "no reference data at " << kReferenceDir;
  const fs::path out = fs::temp_directory_path() / ("esdslam_segment_cmd_" + std::to_string(::getpid()));
  const std::string image = (kReferenceDir / "bonn_crowd_1548339830.60015.png").string();
  const std::string ok = program.string() + " segment " + image + " --overlay --out " + out.string() + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(ok.c_str()), 0) << ok;
  const cv::Mat labels = cv::imread((out / "bonn_crowd_1548339830.60015.labels.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(labels.type(), CV_8UC1);
  EXPECT_EQ(labels.size(), cv::Size(640, 480));
  EXPECT_GT(cv::countNonZero(labels == kVocPersonClass), 0.05 * static_cast<double>(labels.total()));
  EXPECT_TRUE(fs::exists(out / "bonn_crowd_1548339830.60015.overlay.png"));
  const fs::path bad = out / "bad_384x288.onnx";
  std::ofstream(bad) << "not a model";
  const std::string fail = program.string() + " segment " + image + " --model " + bad.string() + " --out " +
                           out.string() + " >/dev/null 2>&1";
  EXPECT_NE(std::system(fail.c_str()), 0);
  fs::remove_all(out);
}

}  // namespace
}  // namespace esdslam
