#include "dense/anchored_voxel_map.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "dense/voxel_grid.h"

namespace esdslam {

namespace {

std::uint16_t ToColorX128(float value_x128) {
  return static_cast<std::uint16_t>(std::clamp(std::lround(value_x128), 0L, 255L * 128L));
}

std::uint8_t FromColorX128(std::uint16_t value_x128) { return static_cast<std::uint8_t>((value_x128 + 64) / 128); }

// Inverse variance of a reading at depth z (sigma ~ z^2), relative to one at 1 m; readings nearer
// than 0.5 m count as at 0.5 m (their noise is no longer dominated by the z^2 term).
float ReadingWeight(float z) {
  const float z_m = std::max(0.5f, z);
  return 1.0f / (z_m * z_m * z_m * z_m);
}

bool SameRef(std::uint32_t anchor_a, std::uint32_t index_a, std::uint32_t anchor_b, std::uint32_t index_b) {
  return anchor_a == anchor_b && index_a == index_b;
}

}  // namespace

AnchoredVoxelMap::AnchoredVoxelMap(double voxel_size, double depth_noise_at_1m)
    : voxel_size_(voxel_size), depth_noise_at_1m_(depth_noise_at_1m) {
  if (!(voxel_size > 0)) throw Error("AnchoredVoxelMap: voxel size must be positive");
  if (!(depth_noise_at_1m >= 0)) throw Error("AnchoredVoxelMap: depth noise must be >= 0");
}

void AnchoredVoxelMap::SetAnchorPose(Anchor* anchor, const Rigid3& world_from_cam) {
  anchor->world_from_cam = world_from_cam;
  anchor->rotation = world_from_cam.rotation_matrix().cast<float>();
  anchor->translation = world_from_cam.translation().cast<float>();
}

std::uint32_t AnchoredVoxelMap::AnchorSlot(long keyframe_id, const Rigid3& world_from_cam) {
  const auto found = slot_of_keyframe_.find(keyframe_id);
  if (found != slot_of_keyframe_.end()) {
    UpdatePoses({{keyframe_id, world_from_cam}});
    return found->second;
  }
  const auto slot = static_cast<std::uint32_t>(anchors_.size());
  anchors_.emplace_back();
  anchors_.back().keyframe_id = keyframe_id;
  SetAnchorPose(&anchors_.back(), world_from_cam);
  slot_of_keyframe_[keyframe_id] = slot;
  return slot;
}

void AnchoredVoxelMap::Integrate(long keyframe_id, const Rigid3& world_from_cam, const PointCloud& points_cam) {
  const std::uint32_t slot = AnchorSlot(keyframe_id, world_from_cam);
  const Eigen::Matrix3f rotation = anchors_[slot].rotation;
  const Eigen::Vector3f translation = anchors_[slot].translation;
  std::vector<StoredPoint>& own = anchors_[slot].points;
  own.reserve(own.size() + points_cam.size());
  for (std::size_t i = 0; i < points_cam.size(); ++i) {
    const Eigen::Vector3f& p = points_cam.points[i];
    if (!p.allFinite() || !(p.squaredNorm() > 0)) continue;
    const Eigen::Vector3f p_world = rotation * p + translation;
    const Rgb8& c = points_cam.colors[i];
    const float color_x128[3] = {128.0f * c.r, 128.0f * c.g, 128.0f * c.b};
    const float weight = ReadingWeight(p.z());
    const std::uint64_t key = VoxelKey(p_world, voxel_size_);
    const auto [it, inserted] = index_.try_emplace(key, PointRef{slot, static_cast<std::uint32_t>(own.size())});
    if (!inserted) {
      Accumulate(it->second, p_world, color_x128, weight);
      continue;
    }
    // Depth noise scatters a surface along the viewing ray: a reading whose voxel is empty but
    // that lies within one voxel of the point in the voxel just before or behind it along the ray
    // is that surface, not a new one.
    const float sigma = static_cast<float>(depth_noise_at_1m_) * p.z() * p.z();
    index_.erase(it);  // (re-added below unless merged; the probe must not find this reading itself)
    const PointRef* near = NearPointOnRay(p_world, (rotation * p).normalized(), std::max(static_cast<float>(voxel_size_), 2.0f * sigma));
    if (near != nullptr) {
      Accumulate(*near, p_world, color_x128, weight);
      continue;
    }
    index_.emplace(key, PointRef{slot, static_cast<std::uint32_t>(own.size())});
    StoredPoint point;
    point.position = p;
    point.weight = weight;
    point.key = key;
    for (int k = 0; k < 3; ++k) point.color_x128[k] = ToColorX128(color_x128[k]);
    own.push_back(point);
    anchors_[slot].max_range = std::max(anchors_[slot].max_range, p.norm());
    ++live_points_;
  }
  own.shrink_to_fit();  // most points usually merge into existing ones: give back the reserve
}

const AnchoredVoxelMap::PointRef* AnchoredVoxelMap::NearPointOnRay(const Eigen::Vector3f& p_world, const Eigen::Vector3f& ray,
                                                                   float radius) const {
  const float voxel = static_cast<float>(voxel_size_);
  // At most kMaxRaySteps voxels each way: with a voxel far below the depth noise (e.g.
  // Dense.voxelSize: 1e-6) the radius spans millions of voxels, and a probe per voxel would
  // never finish. The default voxel reaches the cap only beyond ~14 m of depth.
  constexpr float kMaxRaySteps = 64;
  const int steps = static_cast<int>(std::clamp(std::ceil(radius / voxel), 1.0f, kMaxRaySteps));
  for (int step = 1; step <= steps; ++step)
    for (const float side : {-1.0f, 1.0f}) {
      const auto it = index_.find(VoxelKey(p_world + (side * step * voxel) * ray, voxel_size_));
      if (it == index_.end()) continue;
      const Anchor& anchor = anchors_[it->second.anchor];
      const Eigen::Vector3f offset = WorldPosition(anchor, anchor.points[it->second.index]) - p_world;
      // Within the radius, and more along the ray than across it (a neighbour on the same surface
      // seen face-on lies across the ray and must stay a point of its own).
      const float along = offset.dot(ray);
      if (offset.squaredNorm() <= radius * radius && along * along > offset.cross(ray).squaredNorm()) return &it->second;
    }
  return nullptr;
}

void AnchoredVoxelMap::Accumulate(const PointRef& ref, const Eigen::Vector3f& p_world, const float color_x128[3], float weight) {
  Anchor& anchor = anchors_[ref.anchor];
  StoredPoint& target = anchor.points[ref.index];
  const Eigen::Vector3f p_anchor = anchor.rotation.transpose() * (p_world - anchor.translation);
  const float total = target.weight + weight;
  const float share = weight / total;
  target.position += share * (p_anchor - target.position);
  for (int k = 0; k < 3; ++k) target.color_x128[k] = ToColorX128(target.color_x128[k] + share * (color_x128[k] - target.color_x128[k]));
  target.weight = total;
  anchor.max_range = std::max(anchor.max_range, target.position.norm());
}

int AnchoredVoxelMap::UpdatePoses(const KeyframePoses& poses, double threshold_voxels) {
  const double threshold = threshold_voxels * voxel_size_;
  std::vector<std::uint32_t> moved;
  for (std::uint32_t slot = 0; slot < anchors_.size(); ++slot) {
    const Anchor& anchor = anchors_[slot];
    const auto pose = poses.find(anchor.keyframe_id);
    if (pose == poses.end()) continue;
    // A point at range r moves by at most |dt| + angle * r.
    const double shift = (pose->second.translation() - anchor.world_from_cam.translation()).norm() +
                         RotationAngle(anchor.world_from_cam.rotation().conjugate() * pose->second.rotation()) * anchor.max_range;
    if (shift > threshold) moved.push_back(slot);
  }
  // Unindex every moved point first, so that no point merges into one that is about to move.
  for (const std::uint32_t slot : moved) {
    const std::vector<StoredPoint>& points = anchors_[slot].points;
    for (std::uint32_t i = 0; i < points.size(); ++i) {
      if (points[i].weight <= 0) continue;
      const auto it = index_.find(points[i].key);
      if (it != index_.end() && SameRef(it->second.anchor, it->second.index, slot, i)) index_.erase(it);
    }
  }
  for (const std::uint32_t slot : moved) {
    reindexed_points_ += anchors_[slot].points.size() - anchors_[slot].holes;
    SetAnchorPose(&anchors_[slot], poses.at(anchors_[slot].keyframe_id));
    for (std::uint32_t i = 0; i < anchors_[slot].points.size(); ++i)
      if (anchors_[slot].points[i].weight > 0) Reinsert(slot, i);
  }
  for (const std::uint32_t slot : moved)
    if (2 * anchors_[slot].holes > anchors_[slot].points.size()) Compact(slot);
  return static_cast<int>(moved.size());
}

void AnchoredVoxelMap::Reinsert(std::uint32_t slot, std::uint32_t index) {
  Anchor& anchor = anchors_[slot];
  StoredPoint& point = anchor.points[index];
  const Eigen::Vector3f p_world = WorldPosition(anchor, point);
  const std::uint64_t key = VoxelKey(p_world, voxel_size_);
  const auto [it, inserted] = index_.try_emplace(key, PointRef{slot, index});
  if (inserted) {
    point.key = key;
    return;
  }
  const float color_x128[3] = {static_cast<float>(point.color_x128[0]), static_cast<float>(point.color_x128[1]),
                               static_cast<float>(point.color_x128[2])};
  Accumulate(it->second, p_world, color_x128, point.weight);
  std::uint8_t& kept_evidence = anchors_[it->second.anchor].points[it->second.index].evidence;
  kept_evidence = std::max(kept_evidence, point.evidence);
  point.weight = 0;
  ++anchor.holes;
  --live_points_;
}

void AnchoredVoxelMap::Compact(std::uint32_t slot) {
  Anchor& anchor = anchors_[slot];
  std::vector<StoredPoint> kept;
  kept.reserve(anchor.points.size() - anchor.holes);
  for (std::uint32_t i = 0; i < anchor.points.size(); ++i) {
    const StoredPoint& point = anchor.points[i];
    if (point.weight <= 0) continue;
    const auto it = index_.find(point.key);
    if (it == index_.end() || !SameRef(it->second.anchor, it->second.index, slot, i))
      throw Error("AnchoredVoxelMap: index out of step with the points (internal error)");
    it->second.index = static_cast<std::uint32_t>(kept.size());
    kept.push_back(point);
  }
  anchor.points.swap(kept);
  anchor.holes = 0;
}

std::size_t AnchoredVoxelMap::CarveFreeSpace(const FreeSpaceView& view, int max_evidence) {
  std::size_t removed = 0;
  for (std::uint32_t slot = 0; slot < anchors_.size(); ++slot) {
    Anchor& anchor = anchors_[slot];
    // view camera <- anchor camera, composed once per anchor
    const Eigen::Matrix3f rotation = view.cam_from_world_rotation() * anchor.rotation;
    const Eigen::Vector3f translation = view.cam_from_world_rotation() * anchor.translation + view.cam_from_world_translation();
    for (std::uint32_t i = 0; i < anchor.points.size(); ++i) {
      StoredPoint& point = anchor.points[i];
      if (point.weight <= 0) continue;
      const FreeSpaceVerdict verdict = view.ClassifyInCamera(rotation * point.position + translation);
      if (UpdateEvidence(verdict, max_evidence, &point.evidence)) continue;
      const auto it = index_.find(point.key);
      if (it != index_.end() && SameRef(it->second.anchor, it->second.index, slot, i)) index_.erase(it);
      point.weight = 0;
      ++anchor.holes;
      --live_points_;
      ++removed;
    }
    if (2 * anchor.holes > anchor.points.size()) Compact(slot);
  }
  carved_points_ += removed;
  return removed;
}

PointCloud AnchoredVoxelMap::Extract(const KeyframePoses& poses) const {
  VoxelGrid grid(voxel_size_);
  for (const Anchor& anchor : anchors_) {
    const auto pose = poses.find(anchor.keyframe_id);
    const Rigid3& world_from_cam = pose == poses.end() ? anchor.world_from_cam : pose->second;
    const Eigen::Matrix3f rotation = world_from_cam.rotation_matrix().cast<float>();
    const Eigen::Vector3f translation = world_from_cam.translation().cast<float>();
    for (const StoredPoint& point : anchor.points) {
      if (point.weight <= 0) continue;
      const Rgb8 color{FromColorX128(point.color_x128[0]), FromColorX128(point.color_x128[1]), FromColorX128(point.color_x128[2])};
      grid.Insert(rotation * point.position + translation, color, point.weight);
    }
  }
  return grid.Extract();
}

std::size_t AnchoredVoxelMap::CountIndexErrors() const {
  std::size_t errors = 0;
  for (std::uint32_t slot = 0; slot < anchors_.size(); ++slot)
    for (std::uint32_t i = 0; i < anchors_[slot].points.size(); ++i) {
      if (anchors_[slot].points[i].weight <= 0) continue;
      const auto it = index_.find(anchors_[slot].points[i].key);
      errors += it == index_.end() || !SameRef(it->second.anchor, it->second.index, slot, i);
    }
  for (const auto& [key, ref] : index_) errors += anchors_[ref.anchor].points[ref.index].weight <= 0;
  return errors;
}

std::size_t AnchoredVoxelMap::memory_bytes() const {
  // libstdc++'s unordered_map: one heap node per entry (next pointer + key + value), rounded up to
  // malloc's 16-byte chunks with its 8-byte header, plus the bucket array of pointers.
  const std::size_t node = (sizeof(void*) + sizeof(std::pair<const std::uint64_t, PointRef>) + 8 + 15) / 16 * 16;
  std::size_t bytes = anchors_.capacity() * sizeof(Anchor) + index_.size() * node + index_.bucket_count() * sizeof(void*);
  for (const Anchor& anchor : anchors_) bytes += anchor.points.capacity() * sizeof(StoredPoint);
  bytes += slot_of_keyframe_.size() * 32 + slot_of_keyframe_.bucket_count() * sizeof(void*);
  return bytes;
}

}  // namespace esdslam
