#pragma once
// Where a run's frames come from. The run loop (system/run_loop.h) asks a FrameSource for one
// frame at a time, in time order, on the tracking thread; it takes the next frame before it
// tracks the current one (look-ahead, so segmentation of frame i+1 overlaps tracking of frame i).
//
// Sources: TumFolderSource (a TUM-layout folder read frame by frame, below), LivePlaybackSource
// (io/live_playback_source.h: any source played on a clock, dropping the frames that arrive
// while the system is busy). A library user's own camera implements this interface (README,
// "Using a camera"). A source that drops frames does not return them and counts them in the next
// returned frame's dropped_before.

#include <atomic>
#include <cstddef>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "io/tum_sequence.h"

namespace esdslam {

// One RGB-D frame as the pipeline takes it (the images are shared, never written afterwards).
struct RgbdFrame {
  double timestamp = 0;  // seconds, the colour image's time (the frame's time)
  cv::Mat bgr;           // CV_8UC3 (or CV_8UC1 grey), OpenCV channel order as decoded
  cv::Mat depth_m;       // CV_32F metres, 0 = invalid; same size as bgr
  int dropped_before = 0;  // frames the source dropped between the frame it returned before and this one
  // A library caller's own knowledge of moving things (empty from the folder and camera sources):
  cv::Mat dynamic_mask;  // CV_8U, nonzero = moving; joins the pipeline's own dynamic mask
  cv::Mat labels;        // CV_8U class ids, the frame's labels with Semantic.segmenter: provided
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // The next frame, or nullopt after the last one. Throws InputError naming the file (or the
  // device) when frames cannot be read (a source may skip single bad frames, see below).
  virtual std::optional<RgbdFrame> Next() = 0;
  // Frames this source will return in all, when known in advance (progress); nullopt for a
  // live source.
  virtual std::optional<std::size_t> frame_count() const = 0;
};

// What TumFolderSource accepts.
struct FolderSourceOptions {
  // A frame whose image cannot be read (missing since the listing, corrupt, wrong type) is
  // skipped with a warning; this many such frames in a row end the run with an InputError.
  int max_consecutive_bad_frames = 10;
  // Every image must have this size (the settings' Camera.width/height); an image of another size
  // is an InputError naming the file (not skipped: the intrinsics do not fit it). Empty: any.
  cv::Size image_size;
  void Check() const;  // throws Error: max_consecutive_bad_frames >= 1, image_size empty or positive
};

// The frames of a TUM-layout sequence (io/tum_sequence.h), read from disk one per Next().
class TumFolderSource final : public FrameSource {
 public:
  // frames: in time order (e.g. the first N of TumSequence::frames()); depth_map_factor as in
  // LoadRgbd.
  TumFolderSource(std::vector<FrameEntry> frames, double depth_map_factor, const FolderSourceOptions& options = {});
  std::optional<RgbdFrame> Next() override;
  // Every listed frame, the skipped ones included.
  std::optional<std::size_t> frame_count() const override { return frames_.size(); }
  // Frames skipped so far because an image could not be read; may be read from another thread
  // than the one calling Next() (a PrefetchingFrameSource's loader).
  std::size_t frames_skipped() const { return skipped_.load(); }

 private:
  std::vector<FrameEntry> frames_;
  double depth_map_factor_;
  FolderSourceOptions options_;
  std::size_t next_ = 0;
  std::atomic<std::size_t> skipped_{0};
};

}  // namespace esdslam
