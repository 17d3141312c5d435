#include "map/map_serialization.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <type_traits>

#include <spdlog/spdlog.h>

#include "common/error.h"

namespace esdslam {
namespace {

constexpr char kMagic[8] = {'E', 'S', 'D', 'M', 'A', 'P', '\0', '\1'};
constexpr std::uint32_t kVersion = 1;

class Writer {
 public:
  explicit Writer(const std::string& path) : path_(path), out_(path, std::ios::binary) {
    if (!out_) throw Error("cannot write map file " + path);
  }
  template <typename T>
  void Put(T value) {
    static_assert(std::is_arithmetic_v<T>);
    out_.write(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  void Bytes(const void* data, std::size_t size) { out_.write(static_cast<const char*>(data), size); }
  void Finish() {
    out_.flush();
    if (!out_) throw Error("writing map file " + path_ + " failed");
  }

 private:
  std::string path_;
  std::ofstream out_;
};

class Reader {
 public:
  explicit Reader(const std::string& path) : path_(path), in_(path, std::ios::binary) {
    if (!in_) throw InputError(path, 0, "a readable map file");
  }
  template <typename T>
  T Get() {
    T value{};
    Bytes(&value, sizeof(T));
    return value;
  }
  void Bytes(void* data, std::size_t size) {
    in_.read(static_cast<char*>(data), size);
    if (!in_) throw InputError(path_, 0, "a complete map file (truncated)");
  }
  [[noreturn]] void Fail(const std::string& what) const { throw InputError(path_, 0, what); }

 private:
  std::string path_;
  std::ifstream in_;
};

void WritePose(Writer& w, const Rigid3& pose) {
  const Quat& q = pose.rotation();
  for (double v : {q.w(), q.x(), q.y(), q.z()}) w.Put(v);
  for (int k = 0; k < 3; ++k) w.Put(pose.translation()[k]);
}

Rigid3 ReadPose(Reader& r) {
  double q[4], t[3];
  for (double& v : q) v = r.Get<double>();
  for (double& v : t) v = r.Get<double>();
  const Quat rotation(q[0], q[1], q[2], q[3]);
  if (!(std::abs(rotation.norm() - 1.0) < 1e-6)) r.Fail("a unit quaternion keyframe pose");
  return Rigid3(rotation.normalized(), Vec3(t[0], t[1], t[2]));
}

void WriteKeyFrame(Writer& w, const KeyFrame& keyframe) {
  const FeatureSet& f = keyframe.features();
  w.Put<std::int64_t>(keyframe.id());
  w.Put<std::int64_t>(keyframe.frame_id());
  w.Put<double>(keyframe.timestamp());
  WritePose(w, keyframe.cam_from_world());
  w.Put<std::uint32_t>(static_cast<std::uint32_t>(f.size()));
  for (int i = 0; i < f.size(); ++i) {
    const cv::KeyPoint& k = f.keypoints[i];
    for (float v : {k.pt.x, k.pt.y, k.size, k.angle, k.response}) w.Put(v);
    w.Put<std::int32_t>(k.octave);
    for (float v : {f.undistorted[i].x, f.undistorted[i].y, f.depth[i], f.right_u[i]}) w.Put(v);
    w.Put<std::uint8_t>(f.is_dynamic[i]);
    w.Bytes(f.descriptor(i), 32);
  }
}

std::shared_ptr<const FeatureSet> ReadFeatures(Reader& r, const std::shared_ptr<const RgbdRig>& rig) {
  const std::uint32_t n = r.Get<std::uint32_t>();
  if (n > 1000000) r.Fail("a keypoint count below 10^6");
  auto f = std::make_shared<FeatureSet>();
  f->rig = rig;
  f->keypoints.resize(n), f->undistorted.resize(n), f->depth.resize(n), f->right_u.resize(n), f->is_dynamic.resize(n);
  f->descriptors.create(static_cast<int>(n), 32, CV_8U);
  std::vector<int> levels(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    cv::KeyPoint& k = f->keypoints[i];
    k.pt.x = r.Get<float>(), k.pt.y = r.Get<float>(), k.size = r.Get<float>(), k.angle = r.Get<float>();
    k.response = r.Get<float>();
    k.octave = r.Get<std::int32_t>();
    if (k.octave < 0 || k.octave >= rig->pyramid.num_levels) r.Fail("keypoint levels within the run's pyramid");
    levels[i] = k.octave;
    f->undistorted[i].x = r.Get<float>(), f->undistorted[i].y = r.Get<float>();
    f->depth[i] = r.Get<float>(), f->right_u[i] = r.Get<float>();
    f->is_dynamic[i] = r.Get<std::uint8_t>();
    r.Bytes(f->descriptors.ptr<unsigned char>(static_cast<int>(i)), 32);
  }
  const PinholeCamera& camera = rig->camera;
  f->grid = std::make_unique<FeatureGrid>(f->undistorted, levels, camera.min_u(), camera.max_u(), camera.min_v(),
                                          camera.max_v());
  return f;
}

void CheckCamera(Reader& r, const RgbdRig& rig) {
  const CameraIntrinsics& c = rig.camera.intrinsics();
  for (double expected : {c.fx, c.fy, c.cx, c.cy})
    if (std::abs(r.Get<double>() - expected) > 1e-6) r.Fail("a map made with the run's camera (fx fy cx cy differ)");
  if (r.Get<std::int32_t>() != c.width || r.Get<std::int32_t>() != c.height) r.Fail("a map with the run's image size");
}

}  // namespace

MapFileSummary SaveMap(const Map& map, const std::string& path) {
  const std::vector<KeyFrame*> keyframes = map.keyframes();
  const std::vector<MapPoint*> points = map.map_points();
  if (keyframes.empty()) throw Error("SaveMap: the map has no keyframes");
  MapFileSummary summary;
  Writer w(path);
  w.Bytes(kMagic, sizeof(kMagic));
  w.Put<std::uint32_t>(kVersion);
  const CameraIntrinsics& c = keyframes.front()->rig().camera.intrinsics();
  for (double v : {c.fx, c.fy, c.cx, c.cy}) w.Put(v);
  w.Put<std::int32_t>(c.width), w.Put<std::int32_t>(c.height);
  w.Put<std::uint64_t>(keyframes.size());
  w.Put<std::uint64_t>(points.size());
  for (const KeyFrame* keyframe : keyframes) WriteKeyFrame(w, *keyframe);
  for (const MapPoint* point : points) {
    const Vec3 position = point->position();
    for (int k = 0; k < 3; ++k) w.Put(position[k]);
    std::vector<std::pair<long, int>> observations;
    for (const auto& [keyframe, index] : point->observations())
      if (!keyframe->is_bad()) observations.emplace_back(keyframe->id(), index);
    w.Put<std::uint32_t>(static_cast<std::uint32_t>(observations.size()));
    for (const auto& [id, index] : observations) w.Put<std::int64_t>(id), w.Put<std::int32_t>(index);
    summary.observations += static_cast<int>(observations.size());
  }
  w.Finish();
  summary.keyframes = static_cast<int>(keyframes.size());
  summary.map_points = static_cast<int>(points.size());
  return summary;
}

MapFileSummary LoadMap(const std::string& path, std::shared_ptr<const RgbdRig> rig, Map* map) {
  if (map->num_keyframes() > 0 || map->num_map_points() > 0) throw Error("LoadMap: the map is not empty");
  Reader r(path);
  char magic[8];
  r.Bytes(magic, sizeof(magic));
  if (std::memcmp(magic, kMagic, sizeof(kMagic)) != 0) r.Fail("an esdslam map file (bad magic)");
  if (r.Get<std::uint32_t>() != kVersion) r.Fail("map file version 1");
  CheckCamera(r, *rig);
  const std::uint64_t num_keyframes = r.Get<std::uint64_t>(), num_points = r.Get<std::uint64_t>();
  if (num_keyframes == 0 || num_keyframes > 10000000 || num_points > 100000000) r.Fail("plausible object counts");
  std::map<long, KeyFrame*> by_file_id;
  std::vector<KeyFrame*> keyframes;
  for (std::uint64_t k = 0; k < num_keyframes; ++k) {
    const long file_id = r.Get<std::int64_t>();
    const long frame_id = r.Get<std::int64_t>();
    const double timestamp = r.Get<double>();
    const Rigid3 cam_from_world = ReadPose(r);
    KeyFrame* keyframe = map->CreateKeyFrame(frame_id, timestamp, ReadFeatures(r, rig), cam_from_world);
    if (!by_file_id.emplace(file_id, keyframe).second) r.Fail("unique keyframe ids");
    map->AddKeyFrame(keyframe);
    keyframes.push_back(keyframe);
  }
  MapFileSummary summary;
  for (std::uint64_t p = 0; p < num_points; ++p) {
    Vec3 position;
    for (int k = 0; k < 3; ++k) position[k] = r.Get<double>();
    const std::uint32_t num_observations = r.Get<std::uint32_t>();
    std::vector<std::pair<KeyFrame*, int>> observations;
    for (std::uint32_t o = 0; o < num_observations; ++o) {
      const auto it = by_file_id.find(r.Get<std::int64_t>());
      const int index = r.Get<std::int32_t>();
      if (it == by_file_id.end()) r.Fail("observations of keyframes in the file");
      if (index < 0 || index >= it->second->features().size()) r.Fail("observation keypoint indices in range");
      if (it->second->map_point(index) == nullptr) observations.emplace_back(it->second, index);
    }
    if (observations.empty()) continue;
    MapPoint* point = map->CreateMapPoint(position, observations.front().first);
    for (const auto& [keyframe, index] : observations) {
      point->AddObservation(keyframe, index, keyframe->features().has_depth(index));
      keyframe->AddMapPoint(point, index);
    }
    point->ComputeDistinctiveDescriptor();
    point->UpdateNormalAndDepth();
    map->AddMapPoint(point);
    ++summary.map_points;
    summary.observations += static_cast<int>(observations.size());
  }
  for (KeyFrame* keyframe : keyframes) keyframe->UpdateConnections();
  summary.keyframes = static_cast<int>(keyframes.size());
  spdlog::info("map: loaded {} keyframes, {} points, {} observations from {}", summary.keyframes, summary.map_points,
               summary.observations, path);
  return summary;
}

}  // namespace esdslam
