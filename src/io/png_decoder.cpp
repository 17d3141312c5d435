#include "io/png_decoder.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>

#include <libdeflate.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {
namespace {

constexpr std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr std::size_t kMaxSide = 1 << 15;  // larger images go to OpenCV (and its own limits)

struct Header {
  std::uint32_t width = 0, height = 0;
  int bit_depth = 0;   // 8 or 16 on the fast path
  int channels = 0;    // 1 (grey), 3 (RGB), 4 (RGBA)
  bool supported = false;
};

std::uint32_t ReadBigEndian32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

Header ParseHeader(const std::uint8_t* data, std::uint32_t length, const std::string& path) {
  if (length != 13) throw InputError(path, 0, "PNG IHDR chunk must be 13 bytes");
  Header header;
  header.width = ReadBigEndian32(data);
  header.height = ReadBigEndian32(data + 4);
  header.bit_depth = data[8];
  const int colour_type = data[9];
  const int interlace = data[12];
  header.channels = colour_type == 0 ? 1 : colour_type == 2 ? 3 : colour_type == 6 ? 4 : 0;
  header.supported = header.channels > 0 && (header.bit_depth == 8 || header.bit_depth == 16) &&
                     data[10] == 0 && data[11] == 0 && interlace == 0 && header.width > 0 &&
                     header.height > 0 && header.width <= kMaxSide && header.height <= kMaxSide;
  return header;
}

// The Sub filter for pixels of kBpp bytes: each byte adds the same byte of the pixel to its left.
template <std::size_t kBpp>
void UnfilterSub(std::uint8_t* row, std::size_t length) {
  std::uint8_t left[kBpp] = {};
  for (std::size_t i = 0; i + kBpp <= length; i += kBpp)
    for (std::size_t c = 0; c < kBpp; ++c) row[i + c] = left[c] = static_cast<std::uint8_t>(row[i + c] + left[c]);
}

// Undoes PNG filter `type` on one row in place; `previous` is the row above, already unfiltered
// (all zeros for the first row); `bpp` is the bytes per pixel.
void Unfilter(int type, std::uint8_t* row, const std::uint8_t* previous, std::size_t length, std::size_t bpp,
              const std::string& path) {
  switch (type) {
    case 0: return;
    case 1:
      switch (bpp) {  // the common pixel sizes keep the running pixel in registers
        case 1: return UnfilterSub<1>(row, length);
        case 2: return UnfilterSub<2>(row, length);
        case 3: return UnfilterSub<3>(row, length);
        case 4: return UnfilterSub<4>(row, length);
        case 6: return UnfilterSub<6>(row, length);
        default:
          for (std::size_t i = bpp; i < length; ++i) row[i] = static_cast<std::uint8_t>(row[i] + row[i - bpp]);
          return;
      }
    case 2:
      for (std::size_t i = 0; i < length; ++i) row[i] = static_cast<std::uint8_t>(row[i] + previous[i]);
      return;
    case 3:
      for (std::size_t i = 0; i < bpp; ++i) row[i] = static_cast<std::uint8_t>(row[i] + (previous[i] >> 1));
      for (std::size_t i = bpp; i < length; ++i)
        row[i] = static_cast<std::uint8_t>(row[i] + ((row[i - bpp] + previous[i]) >> 1));
      return;
    case 4:
      for (std::size_t i = 0; i < bpp; ++i) row[i] = static_cast<std::uint8_t>(row[i] + previous[i]);
      for (std::size_t i = bpp; i < length; ++i) {
        const int a = row[i - bpp], b = previous[i], c = previous[i - bpp];
        const int pa = std::abs(b - c), pb = std::abs(a - c), pc = std::abs(a + b - 2 * c);
        const int predictor = (pa <= pb && pa <= pc) ? a : (pb <= pc ? b : c);
        row[i] = static_cast<std::uint8_t>(row[i] + predictor);
      }
      return;
    default: throw InputError(path, 0, "PNG row filter " + std::to_string(type) + " is not one of 0-4");
  }
}

// Converts the unfiltered rows (RGB(A) order, big-endian 16-bit) to the Mat cv::imread returns:
// BGR(A) order, host-order 16-bit samples.
void CopyRgbRow(const std::uint8_t* source, int width, std::uint8_t* target) {
  for (int x = 0; x < width; ++x, source += 3, target += 3) {
    target[0] = source[2];
    target[1] = source[1];
    target[2] = source[0];
  }
}

template <typename Sample>
void CopyRow(const std::uint8_t* source, int width, int channels, Sample* target) {
  const bool swap_red_blue = channels >= 3;
  for (int x = 0; x < width; ++x, target += channels) {
    for (int c = 0; c < channels; ++c) {
      const int from = swap_red_blue && c < 3 ? 2 - c : c;
      if constexpr (sizeof(Sample) == 1) {
        target[c] = source[x * channels + from];
      } else {
        const std::uint8_t* sample = source + 2 * (x * channels + from);
        target[c] = static_cast<Sample>((sample[0] << 8) | sample[1]);
      }
    }
  }
}

cv::Mat ToMat(const Header& header, const std::uint8_t* rows, std::size_t stride) {
  const int depth = header.bit_depth == 16 ? CV_16U : CV_8U;
  cv::Mat image(static_cast<int>(header.height), static_cast<int>(header.width), CV_MAKETYPE(depth, header.channels));
  for (int y = 0; y < image.rows; ++y) {
    const std::uint8_t* source = rows + static_cast<std::size_t>(y) * stride + 1;
    if (depth == CV_8U && header.channels == 1) std::memcpy(image.ptr(y), source, stride - 1);
    else if (depth == CV_8U && header.channels == 3) CopyRgbRow(source, image.cols, image.ptr<std::uint8_t>(y));
    else if (depth == CV_8U) CopyRow(source, image.cols, header.channels, image.ptr<std::uint8_t>(y));
    else CopyRow(source, image.cols, header.channels, image.ptr<std::uint16_t>(y));
  }
  return image;
}

struct DecompressorDeleter {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

// Inflates the image data into exactly `expected` bytes of `rows` (a buffer the thread reuses, so
// that large frames do not fault in fresh pages every time).
void Inflate(const std::uint8_t* compressed, std::size_t size, std::size_t expected, std::vector<std::uint8_t>* rows,
             const std::string& path) {
  thread_local std::unique_ptr<libdeflate_decompressor, DecompressorDeleter> decompressor(
      libdeflate_alloc_decompressor());
  if (decompressor == nullptr) throw Error("libdeflate: cannot allocate a decompressor");
  if (rows->size() < expected) rows->resize(expected);
  std::size_t produced = 0;
  const libdeflate_result result =
      libdeflate_zlib_decompress(decompressor.get(), compressed, size, rows->data(), expected, &produced);
  if (result != LIBDEFLATE_SUCCESS || produced != expected)
    throw InputError(path, 0, "PNG image data does not inflate to the size its header gives");
}

}  // namespace

std::optional<cv::Mat> DecodePng(const std::uint8_t* bytes, std::size_t size, const std::string& path) {
  if (size < 8 || !std::equal(std::begin(kSignature), std::end(kSignature), bytes)) return std::nullopt;
  thread_local std::vector<std::uint8_t> joined, rows;  // reused: see Inflate
  Header header;
  const std::uint8_t* compressed = nullptr;  // the one IDAT chunk's data, or `joined`
  std::size_t compressed_size = 0;
  int data_chunks = 0;
  joined.clear();
  for (std::size_t at = 8;;) {
    if (size - at < 12) throw InputError(path, 0, "PNG ends inside a chunk (no IEND chunk)");
    const std::uint32_t length = ReadBigEndian32(bytes + at);
    if (length > size - at - 12) throw InputError(path, 0, "PNG chunk runs past the end of the file");
    const std::uint8_t* type = bytes + at + 4;
    const std::uint8_t* data = type + 4;
    const std::uint32_t crc = static_cast<std::uint32_t>(libdeflate_crc32(0, type, length + 4));
    if (crc != ReadBigEndian32(data + length)) throw InputError(path, 0, "PNG chunk CRC mismatch");
    const std::string name(reinterpret_cast<const char*>(type), 4);
    if (at == 8 && name != "IHDR") throw InputError(path, 0, "PNG does not start with an IHDR chunk");
    if (name == "IHDR") header = ParseHeader(data, length, path);
    if (!header.supported || name == "PLTE" || name == "tRNS") return std::nullopt;
    if (name == "IEND") break;
    if (name == "IDAT" && data_chunks++ == 0) compressed = data, compressed_size = length;
    else if (name == "IDAT") joined.insert(joined.end(), data, data + length);
    at += 12 + std::size_t{length};
  }
  if (data_chunks > 1) {
    joined.insert(joined.begin(), compressed, compressed + compressed_size);
    compressed = joined.data(), compressed_size = joined.size();
  }
  const std::size_t bpp = static_cast<std::size_t>(header.channels) * header.bit_depth / 8;
  const std::size_t stride = 1 + header.width * bpp;
  // Deflate expands at most 1032:1; a header promising more than that is damaged (and would
  // otherwise make us allocate gigabytes for a tiny file).
  if (stride * header.height > 1032 * compressed_size + 1024)
    throw InputError(path, 0, "PNG image data is too short for the size its header gives");
  Inflate(compressed, compressed_size, stride * header.height, &rows, path);
  const std::vector<std::uint8_t> zeros(stride, 0);
  for (std::size_t y = 0; y < header.height; ++y) {
    std::uint8_t* row = rows.data() + y * stride;
    const std::uint8_t* previous = y == 0 ? zeros.data() + 1 : row - stride + 1;
    Unfilter(row[0], row + 1, previous, stride - 1, bpp, path);
  }
  return ToMat(header, rows.data(), stride);
}

cv::Mat ReadImageUnchanged(const std::string& path) {
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file) return {};
  const std::streamoff size = file.tellg();
  if (size <= 0) return {};
  thread_local std::vector<std::uint8_t> bytes;  // reused: see Inflate
  bytes.resize(static_cast<std::size_t>(size));
  file.seekg(0);
  if (!file.read(reinterpret_cast<char*>(bytes.data()), size)) return {};
  if (std::optional<cv::Mat> image = DecodePng(bytes.data(), bytes.size(), path)) return *image;
  return cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
}

}  // namespace esdslam
