#include "synth/synthetic_scene.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <opencv2/core/utility.hpp>

#include "common/error.h"
#include "synth/synth_layout.h"

namespace esdslam {
namespace {

// Fixed directional light (world frame, unit) for view-independent (Lambertian) face shading.
const Vec3 kLight = Vec3(0.4, -0.3, 0.866).normalized();

// Per-frame view of a box from the camera: ray directions in the camera frame with z = 1 map
// to the box frame by box_from_cam, so the ray parameter t equals the depth z.
struct BoxView {
  const TexturedBox* box = nullptr;
  Mat3 box_from_cam;
  Vec3 cam_in_box;
  std::array<float, 6> shade{};
  // Conservative image rectangle of the box's projection (pixels, inclusive), for culling.
  double min_u = -1e9, max_u = 1e9, min_v = -1e9, max_v = 1e9;
};

// Bounds the projection of the box by its projected corners (all image if a corner is not in
// front of the camera, e.g. the camera inside the room).
void ComputeImageBounds(BoxView& view, const Rigid3& cam_from_box, const PinholeCamera& camera) {
  double min_u = 1e9, max_u = -1e9, min_v = 1e9, max_v = -1e9;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 h = view.box->half_size;
    const Vec3 p = cam_from_box * Vec3(corner & 1 ? h.x() : -h.x(), corner & 2 ? h.y() : -h.y(), corner & 4 ? h.z() : -h.z());
    if (p.z() < 1e-3) return;  // keep the whole image
    const Vec2 pixel = camera.Project(p);
    min_u = std::min(min_u, pixel.x());
    max_u = std::max(max_u, pixel.x());
    min_v = std::min(min_v, pixel.y());
    max_v = std::max(max_v, pixel.y());
  }
  view.min_u = min_u - 1.0;
  view.max_u = max_u + 1.0;
  view.min_v = min_v - 1.0;
  view.max_v = max_v + 1.0;
}

struct PixelHit {
  double t = 0;
  int view = -1;
  int face = -1;
};

// Nearest hit among `candidates` (indices into views whose bounds contain the row).
PixelHit TraceCameraRay(const std::vector<BoxView>& views, const std::vector<int>& candidates, double u,
                        const Vec3& dir_cam) {
  PixelHit best;
  best.t = std::numeric_limits<double>::infinity();
  for (const int i : candidates) {
    if (u < views[i].min_u || u > views[i].max_u) continue;
    double t;
    int face;
    if (IntersectBox(*views[i].box, views[i].cam_in_box, views[i].box_from_cam * dir_cam, 1e-6, &t, &face) &&
        t < best.t) {
      best.t = t;
      best.view = i;
      best.face = face;
    }
  }
  return best;
}

cv::Vec3f HitColour(const std::vector<BoxView>& views, const Vec3& dir_cam, const PixelHit& hit) {
  if (hit.view < 0) return cv::Vec3f(0, 0, 0);
  const BoxView& view = views[hit.view];
  const Vec3 point_box = view.cam_in_box + hit.t * (view.box_from_cam * dir_cam);
  return SampleBoxTexture(*view.box, hit.face, point_box) * view.shade[hit.face];
}

}  // namespace

SyntheticScene::SyntheticScene(const SynthOptions& options) : options_(options) {
  options_.Check();
  camera_ = PinholeCamera(options_.intrinsics);
  std::mt19937 rng(options_.seed);
  BuildStaticScene(rng);
  BuildMovers(rng);
}

void SyntheticScene::BuildStaticScene(std::mt19937& rng) {
  const SceneLayout layout = MakeSceneLayout(options_);
  TexturedBox room;
  room.half_size = layout.room_half_size;
  room.inside_out = true;
  room.texel_m = options_.texel_m;
  TextureBox(room, layout.room_style, rng);
  boxes_.push_back(std::move(room));
  static_centres_.push_back(Vec3(0.0, 0.0, layout.room_half_size.z()));
  for (const StaticBox& piece : layout.furniture) {
    TexturedBox box;
    box.half_size = piece.half_size;
    box.texel_m = options_.texel_m;
    TextureBox(box, layout.furniture_style, rng);
    boxes_.push_back(std::move(box));
    static_centres_.push_back(piece.centre);
  }
  first_mover_box_ = static_cast<int>(boxes_.size());
  if (options_.moved_box >= static_cast<int>(layout.furniture.size()))
    throw Error(fmt::format("synth: moved_box {} but the layout has {} pieces of furniture", options_.moved_box, layout.furniture.size()));
}

void SyntheticScene::BuildMovers(std::mt19937& rng) {
  mover_paths_ = MakeMoverPaths(options_, rng);
  for (std::size_t k = 0; k < mover_paths_.size(); ++k) AddPersonBox(MoverHalfSize(options_), rng);
  if (options_.close_pass_time >= 0) {
    close_pass_box_ = static_cast<int>(boxes_.size());
    AddPersonBox(ClosePassHalfSize(options_), rng);
  }
  if (options_.blocked_frame >= 0) {
    blocker_box_ = static_cast<int>(boxes_.size());
    AddPersonBox(BlockerHalfSize(), rng);
    // Out of focus and unlit at the lens: dark, with little contrast left.
    for (cv::Mat& texture : boxes_.back().face_textures) texture.convertTo(texture, -1, 0.12, 4.0);
  }
}

void SyntheticScene::AddPersonBox(const Vec3& half_size, std::mt19937& rng) {
  std::uniform_int_distribution<int> level(20, 235);
  TexturedBox box;
  box.half_size = half_size;
  box.object_id = static_cast<int>(boxes_.size()) - first_mover_box_ + 1;
  box.texel_m = 0.004;
  TextureStyle shirt;  // own colours and finer shapes: clothing
  shirt.base_bgr = cv::Vec3b(level(rng), level(rng), level(rng));
  shirt.scales_m = {0.2, 0.1, 0.05, 0.03};
  shirt.coverage = {0.4, 0.4, 0.3, 0.15};
  shirt.colour_probability = 0.8;
  shirt.posters_per_m2 = 0.0;
  TextureBox(box, shirt, rng);
  TextureStyle trousers = shirt;
  trousers.base_bgr = cv::Vec3b(level(rng), level(rng), level(rng));
  for (int face = 0; face < 4; ++face) {  // side faces: rows run along z from the bottom up
    cv::Mat& texture = box.face_textures[face];
    const int rows = static_cast<int>(0.45 * texture.rows);
    const double width_m = texture.cols * box.texel_m;
    MakeTexture(width_m, rows * box.texel_m, box.texel_m, trousers, rng)
        .copyTo(texture(cv::Rect(0, 0, texture.cols, rows)));
  }
  boxes_.push_back(std::move(box));
}

std::vector<StampedPose> SyntheticScene::GroundTruth() const {
  std::vector<StampedPose> poses;
  for (int i = 0; i < num_frames(); ++i) poses.push_back({Timestamp(i), WorldFromCam(i)});
  return poses;
}

Rigid3 SyntheticScene::WorldFromBox(int box, double time) const {
  if (box < first_mover_box_) {
    const bool moved = options_.moved_box >= 0 && box == options_.moved_box + 1 && time >= options_.moved_box_time;  // box 0: room
    return Rigid3(Quat::Identity(), static_centres_[box] + (moved ? options_.moved_box_offset : Vec3::Zero()));
  }
  if (box == close_pass_box_) return ClosePassPose(options_, time);
  if (box == blocker_box_) return BlockerPose(options_, time);
  const int mover = box - first_mover_box_;
  return Rigid3(Quat::Identity(), MoverCentreAt(mover_paths_[mover], boxes_[box].half_size, time));
}

SynthRayHit SyntheticScene::CastRay(const Vec3& origin, const Vec3& dir, double time) const {
  SynthRayHit best;
  best.t = std::numeric_limits<double>::infinity();
  for (int i = 0; i < static_cast<int>(boxes_.size()); ++i) {
    const Rigid3 box_from_world = WorldFromBox(i, time).inverse();
    double t;
    int face;
    if (IntersectBox(boxes_[i], box_from_world * origin, box_from_world.rotation() * dir, 1e-9, &t, &face) &&
        t < best.t) {
      best = {t, i, face, boxes_[i].object_id};
    }
  }
  return best;
}

SynthFrame SyntheticScene::RenderFrame(int index) const {
  const std::uint32_t noise_seed = options_.seed * 2654435761u + static_cast<std::uint32_t>(index);
  SynthFrame frame =
      options_.readout_time_s > 0
          ? RenderRolling([this](double time) { return CameraPoseAt(options_, time); }, FrameTime(index), noise_seed)
          : Render(WorldFromCam(index), FrameTime(index), noise_seed);
  frame.index = index;
  frame.timestamp = Timestamp(index);
  frame.depth_timestamp = DepthTimestamp(index);
  return frame;
}

namespace {

// Ray casts rows [rows.start, rows.end) of `frame` (images already allocated).
void RenderRows(const std::vector<BoxView>& views, const PinholeCamera& camera, int supersampling,
                const cv::Range& rows, SynthFrame& frame) {
  const int ss = supersampling;
  const double fx = camera.fx(), fy = camera.fy(), cx = camera.cx(), cy = camera.cy();
  std::vector<int> candidates;
  for (int v = rows.start; v < rows.end; ++v) {
    candidates.clear();
    for (int i = 0; i < static_cast<int>(views.size()); ++i) {
      if (v + 0.5 >= views[i].min_v && v - 0.5 <= views[i].max_v) candidates.push_back(i);
    }
    auto* bgr = frame.bgr.ptr<cv::Vec3b>(v);
    auto* depth = frame.depth_m.ptr<float>(v);
    auto* mask = frame.mover_mask.ptr<uchar>(v);
    auto* surface = frame.surface_id.ptr<int>(v);
    for (int u = 0; u < camera.width(); ++u) {
      const Vec3 centre_dir((u - cx) / fx, (v - cy) / fy, 1.0);
      const PixelHit centre = TraceCameraRay(views, candidates, u, centre_dir);
      const bool hit = centre.view >= 0;
      depth[u] = hit ? static_cast<float>(centre.t) : 0.f;
      mask[u] = hit ? static_cast<uchar>(views[centre.view].box->object_id) : 0;
      surface[u] = hit ? 6 * centre.view + centre.face : -1;
      cv::Vec3f colour(0, 0, 0);
      if (ss == 1) {
        colour = HitColour(views, centre_dir, centre);
      } else {  // ss x ss sub-pixel rays on a regular grid
        for (int sy = 0; sy < ss; ++sy) {
          for (int sx = 0; sx < ss; ++sx) {
            const Vec3 dir((u + (sx + 0.5) / ss - 0.5 - cx) / fx, (v + (sy + 0.5) / ss - 0.5 - cy) / fy, 1.0);
            colour += HitColour(views, dir, TraceCameraRay(views, candidates, u, dir));
          }
        }
        colour *= 1.0f / static_cast<float>(ss * ss);
      }
      bgr[u] = cv::Vec3b(cv::saturate_cast<uchar>(colour[0]), cv::saturate_cast<uchar>(colour[1]),
                         cv::saturate_cast<uchar>(colour[2]));
    }
  }
}

// Depth noise and range limits: sequential, so the noise is a fixed function of noise_seed.
void FinishDepth(const SynthOptions& options, std::uint32_t noise_seed, cv::Mat& depth_m) {
  std::mt19937 rng(noise_seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int v = 0; v < depth_m.rows; ++v) {
    auto* depth = depth_m.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; ++u) {
      double z = depth[u];
      if (options.depth_noise_at_1m > 0 && z > 0) z += options.depth_noise_at_1m * z * z * normal(rng);
      depth[u] = (z > 0 && z >= options.min_depth_m && z <= options.max_depth_m) ? static_cast<float>(z) : 0.f;
    }
  }
}

// Sensor noise on the colour image, drawn from its own stream of noise_seed.
void AddImageNoise(double sigma, std::uint32_t noise_seed, cv::Mat& bgr) {
  if (!(sigma > 0)) return;
  std::mt19937 rng(noise_seed ^ 0x9e3779b9u);
  std::normal_distribution<double> normal(0.0, sigma);
  for (int v = 0; v < bgr.rows; ++v) {
    auto* row = bgr.ptr<uchar>(v);
    for (int k = 0; k < bgr.cols * 3; ++k) row[k] = cv::saturate_cast<uchar>(row[k] + normal(rng));
  }
}

// Every box as seen from world_from_cam at `time` (seconds since frame 0).
std::vector<BoxView> MakeViews(const SyntheticScene& scene, const Rigid3& world_from_cam, double time) {
  const std::vector<TexturedBox>& boxes = scene.boxes();
  std::vector<BoxView> views(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Rigid3 world_from_box = scene.WorldFromBox(static_cast<int>(i), time);
    const Rigid3 box_from_cam = world_from_box.inverse() * world_from_cam;
    views[i].box = &boxes[i];
    views[i].box_from_cam = box_from_cam.rotation_matrix();
    views[i].cam_in_box = box_from_cam.translation();
    ComputeImageBounds(views[i], box_from_cam.inverse(), scene.camera());
    for (int face = 0; face < 6; ++face) {
      const Vec3 normal_world = world_from_box.rotation() * FaceNormal(boxes[i], face);
      views[i].shade[face] = static_cast<float>(0.7 + 0.3 * normal_world.dot(kLight));
    }
  }
  return views;
}

}  // namespace

SynthFrame SyntheticScene::AllocateFrame(const Rigid3& world_from_cam, double time) const {
  const int width = camera_.width(), height = camera_.height();
  SynthFrame frame;
  frame.world_from_cam = world_from_cam;
  frame.timestamp = options_.first_timestamp + time;
  frame.depth_timestamp = frame.timestamp + options_.depth_time_offset;
  frame.bgr.create(height, width, CV_8UC3);
  frame.depth_m.create(height, width, CV_32F);
  frame.mover_mask.create(height, width, CV_8U);
  frame.surface_id.create(height, width, CV_32S);
  return frame;
}

SynthFrame SyntheticScene::Render(const Rigid3& world_from_cam, double time, std::uint32_t noise_seed) const {
  const std::vector<BoxView> views = MakeViews(*this, world_from_cam, time);
  SynthFrame frame = AllocateFrame(world_from_cam, time);
  // Pixels are independent, so the parallel rendering is deterministic.
  cv::parallel_for_(cv::Range(0, camera_.height()),
                    [&](const cv::Range& rows) { RenderRows(views, camera_, options_.supersampling, rows, frame); });
  FinishDepth(options_, noise_seed, frame.depth_m);
  AddImageNoise(options_.image_noise_sigma, noise_seed, frame.bgr);
  return frame;
}

double SyntheticScene::RowTime(double time, int row) const {
  return time + RowTimeOffset(row, camera_.height(), options_.readout_time_s);
}

SynthFrame SyntheticScene::RenderRolling(const std::function<Rigid3(double)>& world_from_cam_at, double time,
                                         std::uint32_t noise_seed) const {
  SynthFrame frame = AllocateFrame(world_from_cam_at(time), time);
  // One band per row: the views (a few dozen boxes) cost little next to the row's
  // width * (1 + supersampling^2) rays. Each row depends on its own time only, so the parallel
  // rendering is deterministic.
  cv::parallel_for_(cv::Range(0, camera_.height()), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      const double row_time = RowTime(time, v);
      const std::vector<BoxView> views = MakeViews(*this, world_from_cam_at(row_time), row_time);
      RenderRows(views, camera_, options_.supersampling, cv::Range(v, v + 1), frame);
    }
  });
  FinishDepth(options_, noise_seed, frame.depth_m);
  AddImageNoise(options_.image_noise_sigma, noise_seed, frame.bgr);
  return frame;
}

}  // namespace esdslam
