// Map files: a saved and reloaded map has the same keyframes, features, points, observations and
// covisibility graph; incompatible or damaged files are rejected.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "map/map.h"
#include "map/map_serialization.h"
#include "core_test_scene.h"
#include "support/temp_path.h"

namespace esdslam {
namespace {

using testing::ProjectLandmarks;
using testing::RandomDescriptors;
using testing::RandomLandmarks;
using testing::TestRig;

// Three keyframes along x looking at 200 landmarks; a point per landmark seen by >= 2 keyframes.
void BuildMap(Map* map) {
  const std::vector<Vec3> landmarks = RandomLandmarks(200);
  const cv::Mat descriptors = RandomDescriptors(200);
  std::vector<KeyFrame*> keyframes;
  std::vector<std::vector<int>> landmark_of_keypoint(3);
  for (int k = 0; k < 3; ++k) {
    const Rigid3 cam_from_world = Rigid3(Quat(Eigen::AngleAxisd(0.02 * k, Vec3::UnitY())), Vec3(-0.1 * k, 0, 0));
    auto features = ProjectLandmarks(landmarks, descriptors, cam_from_world, true, &landmark_of_keypoint[k]);
    KeyFrame* keyframe = map->CreateKeyFrame(10 * k, 0.5 * k, features, cam_from_world);
    map->AddKeyFrame(keyframe);
    keyframes.push_back(keyframe);
  }
  for (int l = 0; l < 200; ++l) {
    MapPoint* point = nullptr;
    for (int k = 0; k < 3; ++k) {
      const auto& ids = landmark_of_keypoint[k];
      const auto it = std::find(ids.begin(), ids.end(), l);
      if (it == ids.end()) continue;
      const int index = static_cast<int>(it - ids.begin());
      if (point == nullptr) point = map->CreateMapPoint(landmarks[l], keyframes[k]);
      point->AddObservation(keyframes[k], index, true);
      keyframes[k]->AddMapPoint(point, index);
    }
    if (point == nullptr) continue;
    point->ComputeDistinctiveDescriptor();
    point->UpdateNormalAndDepth();
    map->AddMapPoint(point);
  }
  for (KeyFrame* keyframe : keyframes) keyframe->UpdateConnections();
}

std::string TempPath(const std::string& name) {
  return testing::TestTempPath("map_test_" + name);
}

TEST(MapSerializationTest, RoundTripKeepsKeyFramesPointsAndGraph) {
  Map original;
  BuildMap(&original);
  const std::string path = TempPath("roundtrip.map");
  const MapFileSummary saved = SaveMap(original, path);
  EXPECT_EQ(saved.keyframes, 3);
  EXPECT_EQ(saved.map_points, original.num_map_points());

  Map loaded;
  const MapFileSummary summary = LoadMap(path, TestRig(), &loaded);
  EXPECT_EQ(summary.keyframes, 3);
  EXPECT_EQ(summary.map_points, saved.map_points);
  EXPECT_EQ(summary.observations, saved.observations);
  const auto a = original.keyframes(), b = loaded.keyframes();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k]->frame_id(), b[k]->frame_id());
    EXPECT_DOUBLE_EQ(a[k]->timestamp(), b[k]->timestamp());
    EXPECT_LT((a[k]->cam_from_world().inverse() * b[k]->cam_from_world()).translation().norm(), 1e-12);
    EXPECT_LT(a[k]->cam_from_world().rotation().angularDistance(b[k]->cam_from_world().rotation()), 1e-12);
    ASSERT_EQ(a[k]->features().size(), b[k]->features().size());
    EXPECT_EQ(cv::norm(a[k]->features().descriptors, b[k]->features().descriptors, cv::NORM_L1), 0.0);
    EXPECT_EQ(a[k]->features().depth, b[k]->features().depth);
    EXPECT_EQ(a[k]->TrackedMapPoints(0), b[k]->TrackedMapPoints(0));
    for (std::size_t j = 0; j < a.size(); ++j) EXPECT_EQ(a[k]->Weight(a[j]), b[k]->Weight(b[j]));
    // Same associations: the point at each keypoint has the same position.
    for (int i = 0; i < a[k]->features().size(); ++i) {
      MapPoint* pa = a[k]->map_point(i);
      MapPoint* pb = b[k]->map_point(i);
      ASSERT_EQ(pa == nullptr, pb == nullptr);
      if (pa != nullptr) {
        EXPECT_LT((pa->position() - pb->position()).norm(), 1e-12);
      }
    }
  }
  EXPECT_EQ(b[1]->parent(), b[0]);
  EXPECT_NE(b[2]->parent(), nullptr);
  std::filesystem::remove(path);
}

TEST(MapSerializationTest, RejectsOtherCameraTruncatedAndForeignFiles) {
  Map original;
  BuildMap(&original);
  const std::string path = TempPath("reject.map");
  SaveMap(original, path);

  auto other = std::make_shared<RgbdRig>(*TestRig());
  CameraIntrinsics k = other->camera.intrinsics();
  k.fx += 1;
  other->camera = PinholeCamera(k);
  Map wrong_camera;
  EXPECT_THROW(LoadMap(path, other, &wrong_camera), InputError);

  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 100);
  Map truncated;
  EXPECT_THROW(LoadMap(path, TestRig(), &truncated), InputError);

  std::ofstream(path, std::ios::binary) << "not a map file at all";
  Map foreign;
  EXPECT_THROW(LoadMap(path, TestRig(), &foreign), InputError);
  EXPECT_THROW(LoadMap(TempPath("missing.map"), TestRig(), &foreign), InputError);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace esdslam
