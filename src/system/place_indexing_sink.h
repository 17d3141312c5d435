#pragma once
// A KeyFrameSink in front of local mapping that indexes each new keyframe for place recognition
// (BoW vector + direct index into the keyframe database) as it is handed over, then forwards it.
// Called by tracking after it released Map::update_mutex.

#include "place/place_recognition.h"
#include "map/keyframe_sink.h"

namespace esdslam {

class PlaceIndexingSink : public KeyFrameSink {
 public:
  // Neither pointer is owned; both must outlive the sink.
  PlaceIndexingSink(KeyFrameSink* next, PlaceRecognition* places) : next_(next), places_(places) {}

  bool AcceptsKeyFrames() const override { return next_->AcceptsKeyFrames(); }
  int QueuedKeyFrames() const override { return next_->QueuedKeyFrames(); }
  void InterruptBundleAdjustment() override { next_->InterruptBundleAdjustment(); }
  bool ReserveKeyFrame() override { return next_->ReserveKeyFrame(); }
  void InsertKeyFrame(KeyFrame* keyframe) override {
    places_->AddKeyFrame(keyframe);
    next_->InsertKeyFrame(keyframe);
  }

 private:
  KeyFrameSink* next_;
  PlaceRecognition* places_;
};

}  // namespace esdslam
