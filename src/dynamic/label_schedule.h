#pragma once
// Which frames the network labels, and from which frame on their labels are used (issue 12).
// Pure bookkeeping on frame ids, no clocks: a run that applies labels when Due() says so (waiting
// for them if needed) labels the same frames and uses the same labels on every run.
//
// Rules, with K = segment_every and L = label_delay_frames:
//   - at most one frame is with the network at a time (in flight): tracking never queues behind it;
//   - frame id is submitted when nothing is in flight and (id % K == 0, or a K-th frame came while
//     the network was busy (owed), or the newest predicted mask is no longer trusted);
//   - newest_wins (`--realtime`): every frame is a candidate: the network takes a frame whenever
//     it is free, and its labels are used as soon as they are back (L is 0);
//   - the network is free again as soon as the labels of the frame in flight, s, are back (Done);
//     they are used from frame s + L on (label_delay). Frames reach the schedule ahead of their
//     masks (the run loop looks ahead, Semantic.lookAhead), so labels are usually back before
//     their own frame is masked. A single-thread run waits for the labels in flight before the
//     next frame is submitted (the network is never found busy there, so which frames are
//     labelled does not depend on timing) and at s + L; a threaded run takes them at the first
//     frame >= s + L at which they are back (tracking never waits).

#include <cstdint>
#include <optional>

namespace esdslam {

struct LabelScheduleOptions {
  int segment_every = 4;       // K >= 1 (frames)
  int label_delay_frames = 0;  // L >= 0 (frames)
  bool newest_wins = false;    // K and L ignored (as 1 and 0)
  void Check() const;          // throws Error naming the value out of bounds
};

class LabelSchedule {
 public:
  explicit LabelSchedule(const LabelScheduleOptions& options);

  // Frame `id` is loaded (ids increase). needs_labels: the newest predicted mask asks for labels.
  // True: send it to the network now (it becomes the frame in flight).
  bool Submit(std::int64_t id, bool needs_labels);
  // Frames from a labelled frame s to the first frame that uses its labels (s + L); 0 for newest_wins.
  int label_delay() const { return options_.newest_wins ? 0 : options_.label_delay_frames; }
  // The in-flight frame's labels are back (or will never come): the network is free.
  void Done() { in_flight_.reset(); }

  std::optional<std::int64_t> in_flight() const { return in_flight_; }
  const LabelScheduleOptions& options() const { return options_; }

 private:
  LabelScheduleOptions options_;
  std::optional<std::int64_t> in_flight_;
  std::optional<std::int64_t> last_id_;
  bool owed_ = false;  // a K-th frame came while the network was busy
};

}  // namespace esdslam
