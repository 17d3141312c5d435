// The fast PNG decoder against OpenCV's: every kind it decodes gives exactly cv::imread's Mat,
// on images that exercise all five row filters; other kinds go to OpenCV; damaged files throw
// an InputError naming the file, never crash.
#include <algorithm>
#include <fstream>
#include <iterator>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/error.h"
#include "io/png_decoder.h"
#include "io/test_files.h"

namespace esdslam {
namespace {

// Smooth gradients plus noise: libpng's adaptive filtering then picks different filters per row.
cv::Mat TestImage(int type, int rows, int cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(0, 9);
  cv::Mat image(rows, cols, type);
  const int channels = image.channels();
  const bool wide = image.depth() == CV_16U;
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < cols; ++x)
      for (int c = 0; c < channels; ++c) {
        const int value = (x * (3 + c) + y * (5 - c) + (y / 7) * noise(rng)) & 0xff;
        if (wide) image.ptr<std::uint16_t>(y)[x * channels + c] = static_cast<std::uint16_t>(value * 251 + x);
        else image.ptr<std::uint8_t>(y)[x * channels + c] = static_cast<std::uint8_t>(value);
      }
  return image;
}

std::vector<std::uint8_t> Encode(const cv::Mat& image, int compression = 3) {
  std::vector<std::uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(".png", image, bytes, {cv::IMWRITE_PNG_COMPRESSION, compression}));
  return bytes;
}

void ExpectSameMat(const cv::Mat& expected, const cv::Mat& actual) {
  ASSERT_EQ(expected.type(), actual.type());
  ASSERT_EQ(expected.size(), actual.size());
  EXPECT_EQ(cv::norm(expected, actual, cv::NORM_INF), 0.0);
}

TEST(PngDecoder, EveryKindDecodedAsOpenCvDoes) {
  for (int type : {CV_8UC1, CV_16UC1, CV_8UC3, CV_8UC4, CV_16UC3, CV_16UC4}) {
    for (int compression : {0, 1, 9}) {
      SCOPED_TRACE("type " + std::to_string(type) + ", compression " + std::to_string(compression));
      const cv::Mat image = TestImage(type, 37, 53, static_cast<unsigned>(type));
      const std::vector<std::uint8_t> bytes = Encode(image, compression);
      const std::optional<cv::Mat> decoded = DecodePng(bytes.data(), bytes.size(), "test.png");
      ASSERT_TRUE(decoded.has_value());
      ExpectSameMat(image, *decoded);
      ExpectSameMat(cv::imdecode(bytes, cv::IMREAD_UNCHANGED), *decoded);
    }
  }
}

TEST(PngDecoder, ReadImageUnchangedReadsFilesAndFallsBack) {
  testing::TempDir dir;
  const cv::Mat depth = TestImage(CV_16UC1, 48, 64, 3);
  ASSERT_TRUE(cv::imwrite(dir.Path("depth.png"), depth));
  ExpectSameMat(depth, ReadImageUnchanged(dir.Path("depth.png")));
  // A bilevel PNG (bit depth 1) and a JPEG are OpenCV's to decode.
  const cv::Mat binary = TestImage(CV_8UC1, 20, 30, 4) > 100;
  ASSERT_TRUE(cv::imwrite(dir.Path("binary.png"), binary, {cv::IMWRITE_PNG_BILEVEL, 1}));
  std::ifstream in(dir.Path("binary.png"), std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_FALSE(DecodePng(bytes.data(), bytes.size(), "binary.png").has_value());
  ExpectSameMat(cv::imread(dir.Path("binary.png"), cv::IMREAD_UNCHANGED), ReadImageUnchanged(dir.Path("binary.png")));
  const cv::Mat colour = TestImage(CV_8UC3, 24, 32, 5);
  ASSERT_TRUE(cv::imwrite(dir.Path("colour.jpg"), colour));
  ExpectSameMat(cv::imread(dir.Path("colour.jpg"), cv::IMREAD_UNCHANGED), ReadImageUnchanged(dir.Path("colour.jpg")));
  EXPECT_TRUE(ReadImageUnchanged(dir.Path("missing.png")).empty());
}

// Every truncation and single-byte corruption of a small PNG returns an image, defers to OpenCV
// or throws an InputError that names the file; a corrupted pixel-data byte is always caught
// (chunk CRC), and a truncated file never decodes.
TEST(PngDecoder, DamagedFilesThrowNamingTheFile) {
  const std::vector<std::uint8_t> good = Encode(TestImage(CV_8UC3, 9, 11, 6));
  for (std::size_t length = 8; length < good.size(); ++length) {
    try {
      EXPECT_FALSE(DecodePng(good.data(), length, "cut.png").has_value()) << "length " << length;
    } catch (const InputError& error) {
      EXPECT_EQ(error.file(), "cut.png");
    }
  }
  int thrown = 0;
  for (std::size_t at = 8; at < good.size(); ++at) {
    std::vector<std::uint8_t> bad = good;
    bad[at] ^= 0x5a;
    try {
      DecodePng(bad.data(), bad.size(), "bad.png");
    } catch (const InputError& error) {
      EXPECT_EQ(error.file(), "bad.png");
      ++thrown;
    }
  }
  EXPECT_GE(thrown, static_cast<int>(good.size()) - 8 - 8);  // all but a few length/type bytes
}

// PNG's chunk CRC (CRC-32, reflected polynomial 0xEDB88320) over `size` bytes.
std::uint32_t Crc32(const std::uint8_t* data, std::size_t size) {
  std::uint32_t crc = 0xffffffffu;
  for (std::size_t i = 0; i < size; ++i) {
    crc ^= data[i];
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return crc ^ 0xffffffffu;
}

TEST(PngDecoder, HeaderPromisingMoreThanTheDataCanHoldThrows) {
  std::vector<std::uint8_t> bytes = Encode(TestImage(CV_8UC1, 4, 4, 7));
  // IHDR data starts at byte 16: claim 30000 x 30000 pixels and fix the chunk's CRC.
  const std::uint8_t side[4] = {0, 0, 0x75, 0x30};
  std::copy(side, side + 4, bytes.begin() + 16);
  std::copy(side, side + 4, bytes.begin() + 20);
  const std::uint32_t crc = Crc32(bytes.data() + 12, 4 + 13);  // type and data of IHDR
  for (int i = 0; i < 4; ++i) bytes[29 + i] = static_cast<std::uint8_t>(crc >> (24 - 8 * i));
  EXPECT_THROW(DecodePng(bytes.data(), bytes.size(), "huge.png"), InputError);
}

}  // namespace
}  // namespace esdslam
