#pragma once
// What tracking needs from local mapping, as an interface in the map layer so that tracking does
// not depend on the mapping stage (the system wires the LocalMapper in).

#include "map/map_types.h"

namespace esdslam {

class KeyFrameSink {
 public:
  virtual ~KeyFrameSink() = default;
  // True when local mapping is idle (not processing a keyframe).
  virtual bool AcceptsKeyFrames() const = 0;
  // Keyframes waiting in the queue.
  virtual int QueuedKeyFrames() const = 0;
  // Asks the running local bundle adjustment to stop early.
  virtual void InterruptBundleAdjustment() = 0;
  // Called by tracking (holding Map::update_mutex) once it decided to create a keyframe, before
  // creating it. False while local mapping is paused for a map correction (loop closing, global
  // BA merge): no keyframe may be created then. A successful reservation is followed by
  // InsertKeyFrame of the new keyframe.
  virtual bool ReserveKeyFrame() { return true; }
  // Hands over a new keyframe (never blocks while holding the map update mutex).
  virtual void InsertKeyFrame(KeyFrame* keyframe) = 0;
};

// Pausing local mapping for a map correction (loop closing, global BA merge), as an interface in
// the map layer so that the loop stage does not depend on the mapping stage.
class MappingControl {
 public:
  virtual ~MappingControl() = default;
  // Refuses new keyframe reservations, then blocks until every keyframe reserved or inserted
  // before has been processed completely (local mapping then stands still). Must not be called
  // holding Map::update_mutex. Pauses nest: each Pause needs one Resume.
  virtual void Pause() = 0;
  virtual void Resume() = 0;
};

// Pause for a scope.
class MappingPause {
 public:
  explicit MappingPause(MappingControl* control) : control_(control) {
    if (control_ != nullptr) control_->Pause();
  }
  ~MappingPause() {
    if (control_ != nullptr) control_->Resume();
  }
  MappingPause(const MappingPause&) = delete;
  MappingPause& operator=(const MappingPause&) = delete;

 private:
  MappingControl* control_;
};

}  // namespace esdslam
