// Fuzz target: the PNG decoder that loads every colour and depth image (io/png_decoder.h).
// ESDSLAM_FUZZ_WRITE_SEED=DIR writes small valid PNGs of each kind it decodes (and two it leaves
// to OpenCV) into DIR and exits; tools/fuzz.sh seeds the corpus with them.
#include <cstdlib>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "common/error.h"
#include "io/png_decoder.h"

namespace {

void WriteSeeds(const std::string& dir) {
  cv::Mat gradient(12, 16, CV_8UC1);
  for (int y = 0; y < gradient.rows; ++y)
    for (int x = 0; x < gradient.cols; ++x) gradient.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(x * 13 + y * 7);
  cv::Mat wide;
  gradient.convertTo(wide, CV_16U, 257.0);
  std::vector<cv::Mat> three = {gradient, gradient * 2, 255 - gradient}, four = {gradient, gradient, gradient, gradient};
  cv::Mat bgr, bgra, bgr16;
  cv::merge(three, bgr);
  cv::merge(four, bgra);
  bgr.convertTo(bgr16, CV_16U, 257.0);
  const std::vector<std::pair<std::string, cv::Mat>> images = {
      {"grey8", gradient}, {"grey16", wide}, {"bgr8", bgr}, {"bgra8", bgra}, {"bgr16", bgr16}};
  for (const auto& [name, image] : images) {
    cv::imwrite(dir + "/" + name + ".png", image);
    cv::imwrite(dir + "/" + name + "_fast.png", image, {cv::IMWRITE_PNG_COMPRESSION, 1});
  }
  cv::imwrite(dir + "/binary.png", gradient > 100, {cv::IMWRITE_PNG_BILEVEL, 1});
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("ESDSLAM_FUZZ_WRITE_SEED")) {
    WriteSeeds(dir);
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    esdslam::DecodePng(data, size, "fuzz.png");
  } catch (const esdslam::Error&) {
  }
  return 0;
}
