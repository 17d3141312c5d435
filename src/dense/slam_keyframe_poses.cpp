#include "dense/slam_keyframe_poses.h"

namespace esdslam {

void SlamKeyframePoses::Register(KeyFrame* keyframe) {
  std::lock_guard<std::mutex> lock(mutex_);
  keyframes_.push_back(keyframe);
}

KeyframePoses SlamKeyframePoses::Poses() const {
  std::vector<KeyFrame*> keyframes;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    keyframes = keyframes_;
  }
  KeyframePoses poses;
  std::lock_guard<std::mutex> map_lock(map_->update_mutex());
  for (KeyFrame* keyframe : keyframes) {
    Rigid3 cam_from_keyframe;
    const KeyFrame* live = LiveAncestor(keyframe, &cam_from_keyframe);
    poses[keyframe->id()] = (cam_from_keyframe * live->cam_from_world()).inverse();
  }
  return poses;
}

}  // namespace esdslam
