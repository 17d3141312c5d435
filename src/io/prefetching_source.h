#pragma once
// Decodes frames ahead on a loader thread (issue 12 item 5): the PNG decoding of a folder
// sequence (about 5-8 ms per colour + depth pair) leaves the tracking thread. Wraps any source
// whose frames do not depend on when they are asked for (a folder, not a camera or --live
// playback, which must be asked at the moment a frame is wanted).
//
// The loader is the project's Worker (common/worker.h): each job reads one frame from the
// wrapped source and puts it, or the error it threw, into a bounded queue of `depth` frames;
// Next() takes the oldest and queues the next read. Frames come in the wrapped source's order,
// and an error reaches the caller after every frame before it, exactly where the wrapped source
// would have thrown it. The wrapped source is only touched by the loader thread while this
// object lives (its own counters must be thread-safe to be read meanwhile: TumFolderSource's are).

#include <cstddef>
#include <exception>
#include <memory>
#include <optional>

#include "common/bounded_queue.h"
#include "common/worker.h"
#include "io/frame_source.h"

namespace esdslam {

class PrefetchingFrameSource final : public FrameSource {
 public:
  // depth: frames decoded ahead, >= 1.
  PrefetchingFrameSource(std::unique_ptr<FrameSource> source, std::size_t depth = 4);
  ~PrefetchingFrameSource() override;  // stops the loader after the reads already queued
  std::optional<RgbdFrame> Next() override;
  std::optional<std::size_t> frame_count() const override { return count_; }

 private:
  struct Read {};  // one frame to read
  struct Loaded {
    std::optional<RgbdFrame> frame;  // nullopt: the wrapped source ended
    std::exception_ptr error;        // what the wrapped source threw
  };
  void Load(Read&);  // the loader's handler

  std::unique_ptr<FrameSource> source_;
  std::optional<std::size_t> count_;
  BoundedQueue<Loaded> loaded_;  // capacity depth + 1: the loader never blocks on it
  bool ended_ = false;           // the loader reached the end or an error (owner thread)
  Worker<Read> loader_;          // last: stopped before the members its handler uses
};

}  // namespace esdslam
