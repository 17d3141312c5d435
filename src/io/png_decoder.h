#pragma once
// A fast decoder for the PNG files RGB-D datasets and cameras write (TUM, Bonn, our synthetic
// sequences): 8- or 16-bit grey, RGB or RGBA, not interlaced, no palette. It inflates the image
// data in one call with libdeflate (about twice zlib's speed) and undoes the row filters itself;
// loading was a fifth of the process CPU of a fast-mode run (5.4 ms per colour image and 3.2 ms
// per depth image with cv::imread). Any other PNG goes to cv::imread.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace esdslam {

// Decodes the `size` bytes at `bytes` as cv::imread(..., IMREAD_UNCHANGED) would: channels in BGR(A) order, 16-bit
// samples in host byte order. Returns std::nullopt when the file is a PNG kind this decoder leaves
// to OpenCV (palette, transparency chunk, bit depth below 8, interlaced) or not a PNG at all.
// Throws InputError (naming `path`) for a PNG that is damaged: bad chunk CRC, truncated data,
// image data that does not inflate to the size the header gives, an unknown row filter.
std::optional<cv::Mat> DecodePng(const std::uint8_t* bytes, std::size_t size, const std::string& path);

// Reads an image file: DecodePng when it applies, cv::imread(IMREAD_UNCHANGED) otherwise. An empty
// Mat when the file cannot be read or decoded by either (as cv::imread).
cv::Mat ReadImageUnchanged(const std::string& path);

}  // namespace esdslam
