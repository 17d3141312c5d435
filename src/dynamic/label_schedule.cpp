#include "dynamic/label_schedule.h"

#include <fmt/format.h>

#include "common/error.h"

namespace esdslam {

void LabelScheduleOptions::Check() const {
  if (segment_every < 1 || segment_every > 1000)
    throw Error(fmt::format("label schedule: segment_every must be in [1, 1000] frames, got {}", segment_every));
  if (label_delay_frames < 0 || label_delay_frames > 100)
    throw Error(fmt::format("label schedule: label_delay_frames must be in [0, 100] frames, got {}", label_delay_frames));
}

LabelSchedule::LabelSchedule(const LabelScheduleOptions& options) : options_(options) { options_.Check(); }

bool LabelSchedule::Submit(std::int64_t id, bool needs_labels) {
  if (last_id_ && id <= *last_id_)
    throw Error(fmt::format("label schedule: frame {} submitted after frame {}", id, *last_id_));
  last_id_ = id;
  const bool scheduled = options_.newest_wins || id % options_.segment_every == 0;
  if (in_flight_) {
    owed_ = owed_ || scheduled;
    return false;
  }
  if (!scheduled && !owed_ && !needs_labels) return false;
  in_flight_ = id;
  owed_ = false;
  return true;
}

}  // namespace esdslam
