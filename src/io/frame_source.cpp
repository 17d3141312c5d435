#include "io/frame_source.h"

#include <utility>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common/error.h"

namespace esdslam {
namespace {

void CheckSize(const cv::Mat& image, const std::string& path, cv::Size expected) {
  if (expected.empty() || image.size() == expected) return;
  throw InputError(path, 0,
                   fmt::format("image is {}x{}, but the settings' Camera.width/Camera.height are {}x{}", image.cols,
                               image.rows, expected.width, expected.height));
}

}  // namespace

void FolderSourceOptions::Check() const {
  if (max_consecutive_bad_frames < 1) throw Error("frame source: max_consecutive_bad_frames must be >= 1");
  if (image_size.width < 0 || image_size.height < 0) throw Error("frame source: image size must not be negative");
}

TumFolderSource::TumFolderSource(std::vector<FrameEntry> frames, double depth_map_factor,
                                 const FolderSourceOptions& options)
    : frames_(std::move(frames)), depth_map_factor_(depth_map_factor), options_(options) {
  if (!(depth_map_factor_ > 0)) throw Error("frame source: depth_map_factor must be > 0");
  options_.Check();
}

std::optional<RgbdFrame> TumFolderSource::Next() {
  int bad_in_a_row = 0;
  while (next_ < frames_.size()) {
    const FrameEntry& entry = frames_[next_++];
    RgbdImages images;
    try {
      images = LoadRgbd(entry, depth_map_factor_);
    } catch (const InputError& e) {
      ++skipped_;
      if (++bad_in_a_row >= options_.max_consecutive_bad_frames)
        throw InputError(e.file(), 0,
                         fmt::format("{} frames in a row cannot be read (limit {}), the last: {}", bad_in_a_row,
                                     options_.max_consecutive_bad_frames, e.what()));
      spdlog::warn("frame {:.6f} skipped: {}", entry.timestamp, e.what());
      continue;
    }
    CheckSize(images.bgr, entry.rgb_path, options_.image_size);
    RgbdFrame frame;
    frame.timestamp = entry.timestamp;
    frame.bgr = std::move(images.bgr);
    frame.depth_m = std::move(images.depth_m);
    return frame;
  }
  return std::nullopt;
}

}  // namespace esdslam
