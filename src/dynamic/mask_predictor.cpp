#include "dynamic/mask_predictor.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {
namespace {

void Require(bool ok, const char* what) {
  if (!ok) throw Error(fmt::format("MaskPredictorOptions: {}", what));
}

// x at flow resolution, in units of `scale` pixels with pixel centres matched:
// (x + 0.5) * scale - 0.5 (scale 1: flow-resolution pixels).
cv::Mat IdentityMap(cv::Size size, float scale_x, float scale_y) {
  cv::Mat map(size, CV_32FC2);
  for (int y = 0; y < size.height; ++y) {
    cv::Vec2f* row = map.ptr<cv::Vec2f>(y);
    for (int x = 0; x < size.width; ++x)
      row[x] = cv::Vec2f((static_cast<float>(x) + 0.5f) * scale_x - 0.5f, (static_cast<float>(y) + 0.5f) * scale_y - 0.5f);
  }
  return map;
}

cv::Mat GreyAt(const cv::Mat& image, cv::Size size) {
  cv::Mat grey = image;
  if (image.channels() == 3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  cv::Mat small;
  cv::resize(grey, small, size, 0, 0, cv::INTER_AREA);
  return small;
}

cv::Mat Dilate(const cv::Mat& mask, int radius_px) {
  if (radius_px <= 0) return mask;
  cv::Mat out;
  cv::dilate(mask, out, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius_px + 1, 2 * radius_px + 1)));
  return out;
}

// Opening then closing with a disc of `radius_px`: removes the specks and thin lines a carried
// mask picks up along boundaries (which region growing would grow into the background) and
// closes thin gaps.
cv::Mat CleanUp(const cv::Mat& mask, int radius_px) {
  if (radius_px <= 0) return mask;
  const cv::Mat disc = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius_px + 1, 2 * radius_px + 1));
  cv::Mat out;
  cv::morphologyEx(mask, out, cv::MORPH_OPEN, disc);
  cv::morphologyEx(out, out, cv::MORPH_CLOSE, disc);
  return out;
}

// Per pixel of frame k: (not disoccluded, P inside frame k-1 and not disoccluded), 0 or 1; and in
// `nearer` (CV_8U 255) the disoccluded pixels that are nearer now than what P saw: a surface moved
// in front (the leading edge of a person), unlike the background uncovered behind one.
cv::Mat StepFactor(const cv::Mat& position_in_prev, const cv::Mat& depth_m, const cv::Mat& prev_depth_m,
                   const MaskPredictorOptions& options, cv::Mat& nearer) {
  const bool test = options.occlusion_abs_tolerance_m > 0 && !depth_m.empty() && !prev_depth_m.empty();
  const int w = position_in_prev.cols, h = position_in_prev.rows;
  cv::Mat factor(position_in_prev.size(), CV_32FC2);
  nearer = cv::Mat::zeros(position_in_prev.size(), CV_8U);
  for (int y = 0; y < h; ++y) {
    const cv::Vec2f* p = position_in_prev.ptr<cv::Vec2f>(y);
    const float* z = test ? depth_m.ptr<float>(y) : nullptr;
    cv::Vec2f* out = factor.ptr<cv::Vec2f>(y);
    std::uint8_t* in_front = nearer.ptr<std::uint8_t>(y);
    for (int x = 0; x < w; ++x) {
      const bool inside = p[x][0] >= 0 && p[x][1] >= 0 && p[x][0] <= w - 1 && p[x][1] <= h - 1;
      bool consistent = true;
      if (test && z[x] > 0) {
        const int u = std::clamp(static_cast<int>(std::lround(p[x][0])), 0, w - 1);
        const int v = std::clamp(static_cast<int>(std::lround(p[x][1])), 0, h - 1);
        const float z_prev = prev_depth_m.at<float>(v, u);
        const double tolerance = options.occlusion_abs_tolerance_m + options.occlusion_depth_sq_tolerance * z[x] * z[x];
        consistent = !(z_prev > 0) || std::abs(z[x] - z_prev) <= tolerance;
        if (!consistent && z[x] < z_prev) in_front[x] = 255;
      }
      out[x] = cv::Vec2f(consistent ? 1.f : 0.f, consistent && inside ? 1.f : 0.f);
    }
  }
  return factor;
}

// Label of flow pixel i: through its path into the source (v >= 0.5), or filled, or kNoLabel.
constexpr std::uint8_t kNoLabel = 255;
std::uint8_t LabelAt(int i, const cv::Vec2f* map, const cv::Vec2f* state, const std::uint8_t* filled,
                     const cv::Mat& source_labels) {
  if (state[i][0] < 0.5f) return filled[i];
  const int u = std::clamp(static_cast<int>(std::lround(map[i][0])), 0, source_labels.cols - 1);
  const int v = std::clamp(static_cast<int>(std::lround(map[i][1])), 0, source_labels.rows - 1);
  return source_labels.at<std::uint8_t>(v, u);
}

// Pixels that failed the disocclusion test because a surface moved in front (`nearer`; the
// leading edge of a person, where the flow is smeared towards the background's) have no label in
// the source: they take the label of a labelled 4-neighbour on the same surface (depth step
// within the fill tolerance), breadth first from the labelled pixels, so the person's. The
// background uncovered behind a person stays unlabelled: what the source saw there was the person.
// `filled` (CV_8U, kNoLabel = none) holds the labels so given.
void FillFromSameSurface(const cv::Mat& map, const cv::Mat& state, const cv::Mat& depth_m, const cv::Mat& nearer,
                         const cv::Mat& source_labels, const MaskPredictorOptions& options, cv::Mat& filled) {
  if (depth_m.empty() || options.fill_abs_tolerance_m <= 0) return;
  const int w = map.cols, h = map.rows;
  const cv::Vec2f* m = map.ptr<cv::Vec2f>();
  const cv::Vec2f* st = state.ptr<cv::Vec2f>();
  const float* z = depth_m.ptr<float>();
  std::uint8_t* f = filled.ptr<std::uint8_t>();
  const std::uint8_t* in_front = nearer.ptr<std::uint8_t>();
  auto unlabelled = [&](int i) { return st[i][0] < 0.5f && f[i] == kNoLabel && in_front[i]; };
  std::vector<int> queue;
  std::vector<std::uint8_t> label_of_queued;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int i = y * w + x;
      if ((st[i][0] < 0.5f && f[i] == kNoLabel) || !(z[i] > 0)) continue;
      if ((x > 0 && unlabelled(i - 1)) || (x + 1 < w && unlabelled(i + 1)) || (y > 0 && unlabelled(i - w)) ||
          (y + 1 < h && unlabelled(i + w))) {
        queue.push_back(i);
        label_of_queued.push_back(LabelAt(i, m, st, f, source_labels));
      }
    }
  }
  const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int p = queue[head], px = p % w, py = p / w;
    const double tolerance = options.fill_abs_tolerance_m + options.fill_depth_sq_tolerance * z[p] * z[p];
    for (int k = 0; k < 4; ++k) {
      const int qx = px + dx[k], qy = py + dy[k];
      if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
      const int q = qy * w + qx;
      if (!unlabelled(q) || !(z[q] > 0) || std::abs(z[q] - z[p]) > tolerance) continue;
      f[q] = label_of_queued[head];
      queue.push_back(q);
      label_of_queued.push_back(f[q]);
    }
  }
}

}  // namespace

void MaskPredictorOptions::Check() const {
  Require(flow_width_px >= 32 && flow_width_px <= 4096, "flow_width_px must be in [32, 4096]");
  Require(flow_finest_scale >= 0 && flow_finest_scale <= 4, "flow_finest_scale must be in [0, 4]");
  Require(flow_patch_size >= 4 && flow_patch_size <= 32, "flow_patch_size must be in [4, 32]");
  Require(flow_patch_stride >= 1 && flow_patch_stride <= flow_patch_size,
          "flow_patch_stride must be in [1, flow_patch_size]");
  Require(flow_gradient_iterations >= 1 && flow_gradient_iterations <= 256, "flow_gradient_iterations must be in [1, 256]");
  Require(flow_variational_iterations >= 0 && flow_variational_iterations <= 100,
          "flow_variational_iterations must be in [0, 100]");
  objects.Check();
  Require(history_frames >= 1 && history_frames <= 1000, "history_frames must be in [1, 1000]");
  Require(age_dilation_px_per_frame >= 0 && age_dilation_px_per_frame <= 20, "age_dilation_px_per_frame must be in [0, 20]");
  Require(max_age_dilation_px >= 0 && max_age_dilation_px <= 100, "max_age_dilation_px must be in [0, 100]");
  Require(occlusion_abs_tolerance_m <= 10, "occlusion_abs_tolerance_m must be <= 10 (<= 0 disables the test)");
  Require(occlusion_depth_sq_tolerance >= 0 && occlusion_depth_sq_tolerance <= 1,
          "occlusion_depth_sq_tolerance must be in [0, 1]");
  Require(fill_abs_tolerance_m <= 10, "fill_abs_tolerance_m must be <= 10 (<= 0 disables the fill)");
  Require(fill_depth_sq_tolerance >= 0 && fill_depth_sq_tolerance <= 1, "fill_depth_sq_tolerance must be in [0, 1]");
  Require(cleanup_radius_px >= 0 && cleanup_radius_px <= 50, "cleanup_radius_px must be in [0, 50]");
  Require(max_trusted_age >= 1 && max_trusted_age <= 1000, "max_trusted_age must be in [1, 1000]");
  Require(max_uncovered_fraction > 0 && max_uncovered_fraction <= 1, "max_uncovered_fraction must be in (0, 1]");
  Require(min_trust >= 0 && min_trust <= 1, "min_trust must be in [0, 1]");
}

MaskPredictor::MaskPredictor(cv::Size image_size, const MaskPredictorOptions& options, const ClassGroups& groups)
    : image_size_(image_size), options_(options), groups_(groups) {
  options_.Check();
  if (image_size.width < 32 || image_size.height < 32) throw Error("MaskPredictor: image size must be at least 32x32");
  const int flow_width = std::min(options_.flow_width_px, image_size.width);
  const int flow_height = std::max(8, static_cast<int>(std::lround(static_cast<double>(flow_width) * image_size.height /
                                                                   image_size.width)));
  flow_size_ = cv::Size(flow_width, flow_height);
  identity_ = IdentityMap(flow_size_, 1.f, 1.f);
  identity_full_units_ = IdentityMap(flow_size_, static_cast<float>(image_size.width) / static_cast<float>(flow_width),
                                     static_cast<float>(image_size.height) / static_cast<float>(flow_height));
  flow_ = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_FAST);
  flow_->setFinestScale(options_.flow_finest_scale);
  flow_->setPatchSize(options_.flow_patch_size);
  flow_->setPatchStride(options_.flow_patch_stride);
  flow_->setGradientDescentIterations(options_.flow_gradient_iterations);
  flow_->setVariationalRefinementIterations(options_.flow_variational_iterations);
}

MaskPredictor::FlowFrame MaskPredictor::MakeFrame(std::int64_t id, const cv::Mat& image, const cv::Mat& depth_m) const {
  FlowFrame frame{id, GreyAt(image, flow_size_), cv::Mat(), cv::Mat(), cv::Mat(), cv::Mat()};
  if (!depth_m.empty()) cv::resize(depth_m, frame.depth_m, flow_size_, 0, 0, cv::INTER_NEAREST);
  if (frames_.empty()) return frame;
  const FlowFrame& prev = frames_.back();
  cv::Mat flow;
  flow_->calc(frame.grey, prev.grey, flow);
  frame.position_in_prev = identity_ + flow;
  frame.step_factor = StepFactor(frame.position_in_prev, frame.depth_m, prev.depth_m, options_, frame.nearer);
  return frame;
}

void MaskPredictor::AddFrame(std::int64_t id, const cv::Mat& image, const cv::Mat& depth_m) {
  if (image.size() != image_size_ || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    throw Error(fmt::format("MaskPredictor::AddFrame: expected a CV_8UC1 or CV_8UC3 image of {}x{}", image_size_.width,
                            image_size_.height));
  if (!depth_m.empty() && (depth_m.size() != image_size_ || depth_m.type() != CV_32FC1))
    throw Error(fmt::format("MaskPredictor::AddFrame: expected a CV_32FC1 depth image of {}x{} (metres)",
                            image_size_.width, image_size_.height));
  if (!frames_.empty() && id <= frames_.back().id)
    throw Error(fmt::format("MaskPredictor::AddFrame: frame ids must increase ({} after {})", id, frames_.back().id));
  FlowFrame frame = MakeFrame(id, image, depth_m);
  if (source_ && !frames_.empty()) CarryOneStep(*source_, frame);
  frames_.push_back(std::move(frame));
  if (static_cast<int>(frames_.size()) > options_.history_frames) frames_.pop_front();
}

bool MaskPredictor::AddLabels(std::int64_t source_id, const cv::Mat& labels) {
  if (labels.size() != image_size_ || labels.type() != CV_8UC1)
    throw Error(fmt::format("MaskPredictor::AddLabels: expected CV_8UC1 labels of {}x{}", image_size_.width,
                            image_size_.height));
  if (frames_.empty() || source_id > frames_.back().id)
    throw Error(fmt::format("MaskPredictor::AddLabels: labels of frame {} before the frame was added", source_id));
  if (source_ && source_id <= source_->id) return false;
  const auto first = std::find_if(frames_.begin(), frames_.end(), [&](const FlowFrame& f) { return f.id == source_id; });
  if (first == frames_.end()) return false;  // left the history (or was never added)
  Source source{source_id,
                labels.clone(),
                identity_full_units_.clone(),
                cv::Mat(flow_size_, CV_32FC2, cv::Scalar(1, 1)),
                cv::Mat(flow_size_, CV_8U, cv::Scalar(kNoLabel)),
                FindSourceObjects(groups_.Masks(labels).dynamic, options_.objects)};
  for (auto it = std::next(first); it != frames_.end(); ++it) CarryOneStep(source, *it);
  source_ = std::move(source);
  return true;
}

void MaskPredictor::CarryOneStep(Source& source, const FlowFrame& frame) const {
  cv::Mat map, state;
  cv::remap(source.map, map, frame.position_in_prev, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  cv::remap(source.state, state, frame.position_in_prev, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  state = state.mul(frame.step_factor);
  cv::Mat filled, consistent;
  cv::remap(source.filled, filled, frame.position_in_prev, cv::noArray(), cv::INTER_NEAREST, cv::BORDER_REPLICATE);
  cv::extractChannel(state, consistent, 0);
  filled.setTo(kNoLabel, consistent >= 0.5f);
  FillFromSameSurface(map, state, frame.depth_m, frame.nearer, source.labels, options_, filled);
  source.map = map;
  source.state = state;
  source.filled = filled;
}

// The dynamic mask of the newest frame: objects moved by their fitted motion; objects without a
// fit keep their pixel-by-pixel carried mask.
cv::Mat MaskPredictor::CarryDynamic(const cv::Mat& per_pixel, const cv::Mat& full_map, const cv::Mat& lost) const {
  if (options_.dynamic_carry == DynamicCarry::kPixels) return per_pixel;
  cv::Mat consistent;
  cv::extractChannel(source_->state, consistent, 0);
  const std::vector<ObjectMotion> motions =
      FitObjectMotions(source_->objects, identity_full_units_, source_->map, consistent, options_.objects);
  cv::Mat dynamic = DrawObjects(source_->objects, motions, image_size_);
  if (std::any_of(motions.begin(), motions.end(), [](const ObjectMotion& m) { return !m.fitted; })) {
    cv::Mat carried_ids;
    cv::remap(source_->objects.ids, carried_ids, full_map, cv::noArray(), cv::INTER_NEAREST, cv::BORDER_REPLICATE);
    carried_ids.setTo(0, lost);
    std::vector<std::uint8_t> unfitted(motions.size() + 1, 0);
    for (std::size_t i = 0; i < motions.size(); ++i) unfitted[i + 1] = motions[i].fitted ? 0 : 255;
    for (int y = 0; y < dynamic.rows; ++y) {
      const std::uint16_t* id = carried_ids.ptr<std::uint16_t>(y);
      std::uint8_t* out = dynamic.ptr<std::uint8_t>(y);
      for (int x = 0; x < dynamic.cols; ++x) out[x] |= unfitted[id[x]];
    }
  }
  if (options_.dynamic_carry == DynamicCarry::kObjectsAndPixels) dynamic |= per_pixel;
  return dynamic;
}

MaskPrediction MaskPredictor::Predict() const {
  MaskPrediction out;
  out.frame_id = newest_frame();
  if (!source_) return out;
  out.source_id = source_->id;
  out.label_age = static_cast<int>(out.frame_id - source_->id);
  if (out.label_age == 0) {
    out.labels = source_->labels;
    out.masks = groups_.Masks(out.labels);
    out.uncovered_fraction = 0;
  } else {
    cv::Mat map;
    cv::resize(source_->map, map, image_size_, 0, 0, cv::INTER_LINEAR);
    cv::remap(source_->labels, out.labels, map, cv::noArray(), cv::INTER_NEAREST, cv::BORDER_REPLICATE);
    cv::Mat consistent, covered, lost;
    cv::extractChannel(source_->state, consistent, 0);
    cv::extractChannel(source_->state, covered, 1);
    cv::resize(consistent < 0.5f, lost, image_size_, 0, 0, cv::INTER_NEAREST);
    cv::Mat filled;
    cv::resize(source_->filled, filled, image_size_, 0, 0, cv::INTER_NEAREST);
    filled.setTo(0, filled == kNoLabel);
    filled.copyTo(out.labels, lost);
    out.uncovered_fraction = static_cast<double>(cv::countNonZero(covered < 0.5f)) / static_cast<double>(covered.total());
    out.masks = groups_.Masks(out.labels);
    out.masks.dynamic = CleanUp(CarryDynamic(out.masks.dynamic, map, lost), options_.cleanup_radius_px);
  }
  const int radius = std::min(options_.max_age_dilation_px,
                              static_cast<int>(std::floor(options_.age_dilation_px_per_frame * out.label_age)));
  out.masks.dynamic = Dilate(out.masks.dynamic, radius);
  const double age_trust = 1.0 - static_cast<double>(out.label_age) / options_.max_trusted_age;
  const double coverage_trust = 1.0 - out.uncovered_fraction / options_.max_uncovered_fraction;
  out.trust = std::clamp(std::min(age_trust, coverage_trust), 0.0, 1.0);
  out.needs_labels = out.trust < options_.min_trust;
  return out;
}

}  // namespace esdslam
