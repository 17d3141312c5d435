// Free-space consistency on synthetic scenes with known geometry (keyframes at the true poses):
// a mover whose labels are missing (it is mapped like static scene) and a static box moved once
// must leave no map point and no occupied OctoMap cell where they stood, once a later keyframe has
// seen that space empty; the static surfaces stay. Also prints the ghost measure
// (dense/ghost_measure.h) of these maps and of the plain presets, every 10th frame, 15 cm margin.
#include <filesystem>

#include "dense/ghost_measure.h"
#include "support/temp_path.h"
#include "synthetic_dense_fixture.h"

namespace esdslam {
namespace {

double DistanceToStaticSceneAt(const SyntheticScene& scene, const Vec3& p, double time) {
  double best = 1e9;
  for (int b = 0; b < static_cast<int>(scene.boxes().size()); ++b)
    if (scene.boxes()[b].object_id == 0) best = std::min(best, DistanceToBoxSurface(scene, b, p, time));
  return best;
}

struct Leftovers {
  std::size_t elements = 0, leftovers = 0;
};

// Within the free-space margin (Dense.freeSpaceMinMargin) of a static surface, a reading cannot be
// told from that surface: a mover's sole on the floor is floor.
constexpr double kOnStatic = 0.03;
// "Later frames have seen the space empty": Dense.freeSpaceMaxEvidence (default 2) of them.
constexpr int kSeenEmptyFrames = 2;

// A leftover: an element (map point, or occupied cell centre with half size `extent`) more than
// kOnStatic + extent from the static scene as it is at the end, within 2 cm + extent of box `box` at
// some keyframe time, and seen empty by kSeenEmptyFrames keyframes after that time (their exact
// depth at the element's pixel lies beyond the element by more than 3 cm + extent).
Leftovers CountLeftovers(const SyntheticScene& scene, int box, const std::vector<Eigen::Vector3f>& elements, double extent,
                         const std::vector<DenseKeyframe>& keyframes) {
  Leftovers count;
  count.elements = elements.size();
  const double end_time = scene.FrameTime(static_cast<int>(keyframes.back().id));
  for (const Eigen::Vector3f& element : elements) {
    const Vec3 p = element.cast<double>();
    if (DistanceToStaticSceneAt(scene, p, end_time) <= kOnStatic + extent) continue;
    double last_there = -1;
    for (const DenseKeyframe& k : keyframes) {
      const double t = scene.FrameTime(static_cast<int>(k.id));
      const Vec3 excess = (scene.WorldFromBox(box, t).inverse() * p).cwiseAbs() - scene.boxes()[box].half_size;
      if (excess.maxCoeff() <= 0.02 + extent) last_there = t;  // inside the box or near it
    }
    if (last_there < 0) continue;
    int seen_empty = 0;
    for (const DenseKeyframe& k : keyframes) {
      if (scene.FrameTime(static_cast<int>(k.id)) <= last_there) continue;
      const Vec3 q = k.world_from_cam.inverse() * p;
      if (q.z() <= 0.1) continue;
      const Vec2 pixel = scene.camera().Project(q);
      const int u = static_cast<int>(std::lround(pixel.x())), v = static_cast<int>(std::lround(pixel.y()));
      if (u < 0 || v < 0 || u >= k.depth_m.cols || v >= k.depth_m.rows) continue;
      seen_empty += k.depth_m.at<float>(v, u) > q.z() + 0.03 + extent;
    }
    count.leftovers += seen_empty >= kSeenEmptyFrames;
  }
  return count;
}

struct BuiltMap {
  PointCloud cloud;
  std::vector<Eigen::Vector3f> cells;
  DenseMapStats stats;
};

BuiltMap Build(const SyntheticScene& scene, const std::vector<DenseKeyframe>& keyframes, bool carving, const std::string& name) {
  DenseOptions options;
  options.voxel_size = kTestVoxel;
  options.depth_noise_at_1m = 0;
  options.free_space_carving = carving;
  DenseMapperOptions mapper;
  mapper.threaded = false;
  DenseMapper dense(scene.camera(), options, {}, mapper);
  for (const DenseKeyframe& k : keyframes) dense.AddKeyframe(k);
  const std::string out = testing::TestTempPath(name);
  DenseOutputFiles files;
  files.pictures = false;
  dense.WriteOutputs(out, files);
  BuiltMap built{dense.CurrentCloud(), ReadOccupiedCellCentres(out + "/octomap.bt"), dense.stats().map};
  std::filesystem::remove_all(out);
  return built;
}

// The ghost measure with the scene's exact depth every 10th frame at the true poses.
void PrintGhostMeasure(const char* what, const SyntheticScene& scene, const BuiltMap& map) {
  GhostMeasure points(scene.camera(), map.cloud.points), cells(scene.camera(), map.cells);
  for (int i = 0; i < scene.num_frames(); i += 10) {
    const SynthFrame frame = scene.RenderFrame(i);
    points.AddFrame(frame.world_from_cam, frame.depth_m);
    cells.AddFrame(frame.world_from_cam, frame.depth_m);
  }
  std::printf("ghost measure %s: points %.3f %% of %zu projections (%zu points), cells %.3f %% (%zu cells)\n", what,
              100 * points.stats().fraction(), points.stats().projections, map.cloud.size(), 100 * cells.stats().fraction(),
              map.cells.size());
}

std::vector<DenseKeyframe> Keyframes(const SyntheticScene& scene, int step, int unmasked_mover) {
  std::vector<DenseKeyframe> keyframes;
  for (int i = 0; i < scene.num_frames(); i += step) {
    keyframes.push_back(SceneKeyframe(scene, i, scene.num_movers() > 0));
    if (!keyframes.back().dynamic_mask.empty()) {
      cv::Mat mask = keyframes.back().dynamic_mask.clone();
      mask.setTo(0, mask == unmasked_mover);  // that mover's labels are missing
      keyframes.back().dynamic_mask = mask;
    }
  }
  return keyframes;
}

TEST(FreeSpaceSyntheticTest, UnmaskedMoverLeavesNothingWhereLaterKeyframesSawEmpty) {
  SynthOptions synth = SynthPreset("dynamic");
  synth.num_frames = 120;
  const SyntheticScene scene(synth);
  const std::vector<DenseKeyframe> keyframes = Keyframes(scene, kKeyframeStep, 1);
  const int box = scene.MoverBox(1);
  const BuiltMap carved = Build(scene, keyframes, true, "free_space_mover");
  const BuiltMap plain = Build(scene, keyframes, false, "free_space_mover_plain");
  const Leftovers points = CountLeftovers(scene, box, carved.cloud.points, 0.0, keyframes);
  const Leftovers cells = CountLeftovers(scene, box, carved.cells, 0.5 * 0.05 * std::sqrt(3.0), keyframes);
  const Leftovers plain_points = CountLeftovers(scene, box, plain.cloud.points, 0.0, keyframes);
  const Leftovers plain_cells = CountLeftovers(scene, box, plain.cells, 0.5 * 0.05 * std::sqrt(3.0), keyframes);
  std::printf("unmasked mover: leftovers %zu of %zu points, %zu of %zu cells (%zu carved); without free-space consistency %zu "
              "points, %zu cells\n",
              points.leftovers, points.elements, cells.leftovers, cells.elements, carved.stats.carved_points,
              plain_points.leftovers, plain_cells.leftovers);
  PrintGhostMeasure("unmasked mover", scene, carved);
  PrintGhostMeasure("unmasked mover, no free-space consistency", scene, plain);
  EXPECT_GT(plain_points.leftovers, 1000u);  // the case is a real one
  EXPECT_EQ(points.leftovers, 0u);
  EXPECT_EQ(cells.leftovers, 0u);
  EXPECT_GE(FractionWithin(scene, carved.cloud, kTestVoxel), FractionWithin(scene, plain.cloud, kTestVoxel) - 1e-9);
}

TEST(FreeSpaceSyntheticTest, MovedBoxLeavesNothingWhereItStoodAndIsMappedWhereItIs) {
  const SyntheticScene scene(SynthPreset("moved_box"));
  const std::vector<DenseKeyframe> keyframes = Keyframes(scene, kKeyframeStep, 0);
  const int box = scene.options().moved_box + 1;
  const BuiltMap carved = Build(scene, keyframes, true, "free_space_box");
  const BuiltMap plain = Build(scene, keyframes, false, "free_space_box_plain");
  const Leftovers points = CountLeftovers(scene, box, carved.cloud.points, 0.0, keyframes);
  const Leftovers cells = CountLeftovers(scene, box, carved.cells, 0.5 * 0.05 * std::sqrt(3.0), keyframes);
  const Leftovers plain_points = CountLeftovers(scene, box, plain.cloud.points, 0.0, keyframes);
  const double end = scene.FrameTime(scene.num_frames() - 1);
  const auto at_new_place = std::count_if(carved.cloud.points.begin(), carved.cloud.points.end(), [&](const Eigen::Vector3f& p) {
    return DistanceToBoxSurface(scene, box, p.cast<double>(), end) <= kTestVoxel;
  });
  std::printf("moved box: leftovers %zu of %zu points, %zu of %zu cells; without free-space consistency %zu points; %ld "
              "points on the box at its new place\n",
              points.leftovers, points.elements, cells.leftovers, cells.elements, plain_points.leftovers,
              static_cast<long>(at_new_place));
  PrintGhostMeasure("moved box", scene, carved);
  PrintGhostMeasure("moved box, no free-space consistency", scene, plain);
  EXPECT_GT(plain_points.leftovers, 1000u);
  EXPECT_EQ(points.leftovers, 0u);
  EXPECT_EQ(cells.leftovers, 0u);
  EXPECT_GT(at_new_place, 2000);
}

TEST(FreeSpaceSyntheticTest, GhostMeasureOfThePresets) {
  for (const char* preset : {"static", "dynamic"}) {
    SynthOptions synth = SynthPreset(preset);
    synth.num_frames = 120;
    const SyntheticScene scene(synth);
    const BuiltMap map = Build(scene, Keyframes(scene, kKeyframeStep, 0), true, "free_space_preset");
    PrintGhostMeasure(preset, scene, map);
    GhostMeasure points(scene.camera(), map.cloud.points);
    for (int i = 0; i < scene.num_frames(); i += 10) {
      const SynthFrame frame = scene.RenderFrame(i);
      points.AddFrame(frame.world_from_cam, frame.depth_m);
    }
    EXPECT_LT(points.stats().fraction(), 0.005) << preset;
    EXPECT_GT(FractionWithin(scene, map.cloud, kTestVoxel), 0.99) << preset;
  }
}

}  // namespace
}  // namespace esdslam
