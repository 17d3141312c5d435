#pragma once
// Frames already in memory, handed out in order (tests, benchmarks, a library caller holding
// decoded images). The images are shared with the vector, not copied: the pipeline never writes
// into them.

#include <cstddef>
#include <optional>
#include <vector>

#include "io/frame_source.h"

namespace esdslam {

class MemoryFrameSource final : public FrameSource {
 public:
  // `frames` must outlive the source.
  explicit MemoryFrameSource(const std::vector<RgbdFrame>& frames) : frames_(frames) {}
  std::optional<RgbdFrame> Next() override {
    if (next_ >= frames_.size()) return std::nullopt;
    return frames_[next_++];
  }
  std::optional<std::size_t> frame_count() const override { return frames_.size(); }

 private:
  const std::vector<RgbdFrame>& frames_;
  std::size_t next_ = 0;
};

}  // namespace esdslam
