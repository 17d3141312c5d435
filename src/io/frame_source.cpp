#include "io/frame_source.h"

#include <utility>

#include "common/error.h"

namespace esdslam {

TumFolderSource::TumFolderSource(std::vector<FrameEntry> frames, double depth_map_factor)
    : frames_(std::move(frames)), depth_map_factor_(depth_map_factor) {
  if (!(depth_map_factor_ > 0)) throw Error("frame source: depth_map_factor must be > 0");
}

std::optional<RgbdFrame> TumFolderSource::Next() {
  if (next_ >= frames_.size()) return std::nullopt;
  const FrameEntry& entry = frames_[next_++];
  RgbdImages images = LoadRgbd(entry, depth_map_factor_);
  return RgbdFrame{entry.timestamp, std::move(images.bgr), std::move(images.depth_m)};
}

}  // namespace esdslam
