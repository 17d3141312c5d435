// The OctoMap of the synthetic room, written by the dense stage and read back with OctoMap's own
// reader: the floor and walls the keyframes saw are occupied, the space between the cameras and
// those surfaces is free, and with masks no mover leaves occupied cells behind (without masks,
// mode none, it does).
#include <filesystem>

#include <octomap/OcTree.h>

#include "dense/octomap_writer.h"
#include "synthetic_dense_fixture.h"
#include "support/temp_path.h"

namespace esdslam {
namespace {

constexpr int kRoomBox = 0;   // SyntheticScene's first box is the room (inside out)
constexpr int kFloorFace = 4;  // face 2 * axis + positive side: -z

struct RoomCheck {
  int floor_rays = 0, floor_occupied = 0;
  int wall_rays = 0, wall_occupied = 0;
  int free_probes = 0, free_found = 0;
};

bool Occupied(const octomap::OcTree& tree, const Vec3& p) {
  const octomap::OcTreeNode* node = tree.search(p.x(), p.y(), p.z());
  return node != nullptr && tree.isNodeOccupied(node);
}

// Casts the true scene's rays through a 32-pixel grid of every keyframe; rays that reach the
// room's floor or walls within the OctoMap range check the surface cell (the cell just before or
// just behind the hit: surfaces can lie on a cell boundary) and the cell half way along the ray.
RoomCheck CheckRoom(const SyntheticScene& scene, const octomap::OcTree& tree, const std::vector<DenseKeyframe>& keyframes,
                    double max_range) {
  RoomCheck check;
  const PinholeCamera& camera = scene.camera();
  for (const DenseKeyframe& keyframe : keyframes) {
    const double time = scene.FrameTime(static_cast<int>(keyframe.id));
    const Vec3 origin = keyframe.world_from_cam.translation();
    for (int v = 16; v < camera.height(); v += 32)
      for (int u = 16; u < camera.width(); u += 32) {
        const Vec3 dir = (keyframe.world_from_cam.rotation() * camera.Backproject(Vec2(u, v), 1.0)).normalized();
        const SynthRayHit hit = scene.CastRay(origin, dir, time);
        if (hit.box != kRoomBox || hit.t > max_range - 0.1 || hit.face == kFloorFace + 1) continue;  // not floor/wall
        const Vec3 surface = origin + hit.t * dir;
        const bool occupied = Occupied(tree, surface - 0.01 * dir) || Occupied(tree, surface + 0.01 * dir);
        if (hit.face == kFloorFace) {
          ++check.floor_rays;
          check.floor_occupied += occupied;
        } else {
          ++check.wall_rays;
          check.wall_occupied += occupied;
        }
        const Vec3 middle = origin + 0.5 * hit.t * dir;
        const octomap::OcTreeNode* node = tree.search(middle.x(), middle.y(), middle.z());
        ++check.free_probes;
        check.free_found += node != nullptr && !tree.isNodeOccupied(node);
      }
  }
  return check;
}

// Occupied cells whose centre lies in a volume a mover occupied at some keyframe time and that
// are not on a static surface.
int GhostCells(const SyntheticScene& scene, const octomap::OcTree& tree, const std::vector<double>& times) {
  int ghosts = 0;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const Vec3 centre(it.getX(), it.getY(), it.getZ());
    if (DistanceToStaticScene(scene, centre) < 1.5 * tree.getResolution()) continue;
    for (int mover = 1; mover <= scene.num_movers(); ++mover) {
      const int box = scene.MoverBox(mover);
      bool inside = false;
      for (const double t : times) {
        const Vec3 p = scene.WorldFromBox(box, t).inverse() * centre;
        inside = inside || (p.cwiseAbs().array() <= scene.boxes()[box].half_size.array()).all();
      }
      ghosts += inside;
    }
  }
  return ghosts;
}

class OctomapSyntheticTest : public SyntheticDenseTest {
 protected:
  static std::unique_ptr<octomap::OcTree> WriteAndRead(const std::vector<DenseKeyframe>& keyframes, const std::string& name) {
    DenseMapperOptions mapper;
    mapper.threaded = false;
    DenseMapper dense(scene_->camera(), Options(), {}, mapper);
    for (const DenseKeyframe& keyframe : keyframes) dense.AddKeyframe(keyframe);
    const std::string path = testing::TestTempPath(name, ".bt");
    const OctomapStats stats = WriteOctomap(path, dense.map(), dense.CurrentPoses());
    EXPECT_GT(stats.occupied_leaves, 1000u);
    auto tree = std::make_unique<octomap::OcTree>(0.1);
    EXPECT_TRUE(tree->readBinary(path));  // OctoMap's own reader
    EXPECT_DOUBLE_EQ(tree->getResolution(), Options().octomap_resolution);
    return tree;
  }
};

TEST_F(OctomapSyntheticTest, FloorAndWallsOccupiedSpaceInFrontFree) {
  const auto tree = WriteAndRead(masked_, "synthetic_masked");
  const RoomCheck check = CheckRoom(*scene_, *tree, masked_, Options().octomap_max_range);
  std::printf("synthetic octomap: floor %d/%d occupied, walls %d/%d occupied, mid-ray free %d/%d\n", check.floor_occupied,
              check.floor_rays, check.wall_occupied, check.wall_rays, check.free_found, check.free_probes);
  ASSERT_GT(check.floor_rays, 100);
  ASSERT_GT(check.wall_rays, 50);  // the far (north) wall is mostly beyond the 4 m OctoMap range
  EXPECT_GE(check.floor_occupied, 0.95 * check.floor_rays) << check.floor_occupied << " / " << check.floor_rays;
  EXPECT_GE(check.wall_occupied, 0.95 * check.wall_rays) << check.wall_occupied << " / " << check.wall_rays;
  EXPECT_GE(check.free_found, 0.95 * check.free_probes) << check.free_found << " / " << check.free_probes;
}

TEST_F(OctomapSyntheticTest, MoversLeaveNoOccupiedCellsWithMasks) {
  const auto masked = WriteAndRead(masked_, "synthetic_masked");
  const auto unmasked = WriteAndRead(unmasked_, "synthetic_unmasked");
  const int ghosts_masked = GhostCells(*scene_, *masked, KeyframeTimes());
  const int ghosts_unmasked = GhostCells(*scene_, *unmasked, KeyframeTimes());
  std::printf("synthetic octomap ghost cells: %d with masks, %d without\n", ghosts_masked, ghosts_unmasked);
  EXPECT_EQ(ghosts_masked, 0);
  EXPECT_GT(ghosts_unmasked, 50);
}

}  // namespace
}  // namespace esdslam
