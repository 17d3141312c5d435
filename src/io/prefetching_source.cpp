#include "io/prefetching_source.h"

#include <utility>

namespace esdslam {

PrefetchingFrameSource::PrefetchingFrameSource(std::unique_ptr<FrameSource> source, std::size_t depth)
    : source_(std::move(source)),
      count_(source_->frame_count()),
      loaded_(depth + 1),
      loader_("frame loader", WorkerMode::kThread, depth + 1, [this](Read& read) { Load(read); }) {
  loader_.Start();
  for (std::size_t i = 0; i < depth; ++i) loader_.Push(Read{});
}

PrefetchingFrameSource::~PrefetchingFrameSource() {
  try {
    loader_.Close();
  } catch (const std::exception&) {
  }
}

void PrefetchingFrameSource::Load(Read&) {
  Loaded loaded;
  try {
    loaded.frame = source_->Next();
  } catch (...) {
    loaded.error = std::current_exception();
  }
  loaded_.Push(std::move(loaded));
}

std::optional<RgbdFrame> PrefetchingFrameSource::Next() {
  if (ended_) return std::nullopt;
  std::optional<Loaded> loaded = loaded_.Pop();  // every queued read pushes exactly one result
  if (!loaded || loaded->error || !loaded->frame) {
    ended_ = true;  // no more reads are queued; results of reads already queued are discarded
    if (loaded && loaded->error) std::rethrow_exception(loaded->error);
    return std::nullopt;
  }
  loader_.Push(Read{});
  return std::move(loaded->frame);
}

}  // namespace esdslam
