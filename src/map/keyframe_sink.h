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
  // Hands over a new keyframe (never blocks while holding the map update mutex).
  virtual void InsertKeyFrame(KeyFrame* keyframe) = 0;
};

}  // namespace esdslam
