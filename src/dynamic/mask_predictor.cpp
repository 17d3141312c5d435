#include "dynamic/mask_predictor.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "dynamic/mask_dilation.h"
#include "dynamic/mask_refine.h"

namespace esdslam {
namespace {

void Require(bool ok, const char* what) {
  if (!ok) throw Error(fmt::format("MaskPredictorOptions: {}", what));
}

cv::Mat GreyAt(const cv::Mat& image, cv::Size size) {
  cv::Mat grey = image;
  if (image.channels() == 3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  cv::Mat small;
  cv::resize(grey, small, size, 0, 0, cv::INTER_AREA);
  return small;
}

cv::Mat Square(int radius_px) { return cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * radius_px + 1, 2 * radius_px + 1)); }

cv::Mat CleanUp(const cv::Mat& mask, int radius_px) {
  if (radius_px <= 0) return mask;
  cv::Mat out;
  cv::morphologyEx(mask, out, cv::MORPH_OPEN, Square(radius_px));
  cv::morphologyEx(out, out, cv::MORPH_CLOSE, Square(radius_px));
  return out;
}

// Nearest-neighbour upsampling of a CV_8U image; exact integer factors (the usual case: 640x480
// from 160x120) copy each pixel into its block (EnlargeNearest), several times cheaper than
// cv::resize.
cv::Mat UpsampleNearest(const cv::Mat& small, cv::Size size) {
  const int fx = size.width / small.cols, fy = size.height / small.rows;
  if (fx == fy && fx * small.cols == size.width && fy * small.rows == size.height) return EnlargeNearest(small, fx, size);
  cv::Mat out;
  cv::resize(small, out, size, 0, 0, cv::INTER_NEAREST);
  return out;
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
  disocclusion.Check();
  Require(cleanup_radius_px >= 0 && cleanup_radius_px <= 50, "cleanup_radius_px must be in [0, 50]");
  Require(age_dilation_px_per_frame >= 0 && age_dilation_px_per_frame <= 20, "age_dilation_px_per_frame must be in [0, 20]");
  Require(max_age_dilation_px >= 0 && max_age_dilation_px <= 100, "max_age_dilation_px must be in [0, 100]");
  Require(history_frames >= 1 && history_frames <= 1000, "history_frames must be in [1, 1000]");
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
  for (int c = 0; c < 256; ++c) dynamic_of_label_[static_cast<std::size_t>(c)] = groups_.IsDynamic(c) ? 255 : 0;
  flow_ = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_FAST);
  flow_->setFinestScale(options_.flow_finest_scale);
  flow_->setPatchSize(options_.flow_patch_size);
  flow_->setPatchStride(options_.flow_patch_stride);
  flow_->setGradientDescentIterations(options_.flow_gradient_iterations);
  flow_->setVariationalRefinementIterations(options_.flow_variational_iterations);
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
  FlowFrame frame{id, GreyAt(image, flow_size_), cv::Mat(), RememberedDepth{}, FlowStep{}};
  if (!depth_m.empty()) cv::resize(depth_m, frame.depth_m, flow_size_, 0, 0, cv::INTER_NEAREST);
  frame.remembered = RememberDepth(frame.depth_m);
  if (!frames_.empty()) {
    cv::Mat backward_flow;
    flow_->calc(frame.grey, frames_.back().grey, backward_flow);
    frame.step = MakeFlowStep(backward_flow, frame.depth_m, frames_.back().remembered, options_.disocclusion,
                              &frame.remembered);
    frames_.back().remembered = RememberedDepth{};  // only the newest frame's is needed
    if (source_) CarryOneStep(frame.step, frame.depth_m, source_->labels, options_.disocclusion, source_->carried);
  }
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
  Source source{source_id, labels.clone(), groups_.Masks(labels).dynamic, StartCarry(flow_size_, image_size_)};
  for (auto it = std::next(first); it != frames_.end(); ++it)
    CarryOneStep(it->step, it->depth_m, source.labels, options_.disocclusion, source.carried);
  source_ = std::move(source);
  return true;
}

MaskPrediction MaskPredictor::Predict() const {
  MaskPrediction out;
  out.frame_id = newest_frame();
  if (!source_) return out;
  out.source_id = source_->id;
  out.label_age = static_cast<int>(out.frame_id - source_->id);
  if (out.label_age == 0) {
    out.labels = source_->labels;
    out.uncovered_fraction = 0;
    out.masks = groups_.Masks(out.labels);
  } else {
    const CarriedImages carried =
        CarriedLabelImages(source_->carried, source_->labels, source_->dynamic, dynamic_of_label_);
    out.uncovered_fraction = carried.uncovered_fraction;
    const SemanticMasks small = groups_.Masks(carried.labels);
    out.labels = UpsampleNearest(carried.labels, image_size_);
    out.masks.potentially_dynamic = UpsampleNearest(small.potentially_dynamic, image_size_);
    out.masks.static_objects = UpsampleNearest(small.static_objects, image_size_);
    cv::resize(carried.dynamic, out.masks.dynamic, image_size_, 0, 0, cv::INTER_LINEAR);
    cv::threshold(out.masks.dynamic, out.masks.dynamic, 127, 255, cv::THRESH_BINARY);
    const int radius = std::min(options_.max_age_dilation_px,
                                static_cast<int>(std::floor(options_.age_dilation_px_per_frame * out.label_age)));
    out.masks.dynamic = DilateEllipse(CleanUp(out.masks.dynamic, options_.cleanup_radius_px), radius);
  }
  const double age_trust = 1.0 - static_cast<double>(out.label_age) / options_.max_trusted_age;
  const double coverage_trust = 1.0 - out.uncovered_fraction / options_.max_uncovered_fraction;
  out.trust = std::clamp(std::min(age_trust, coverage_trust), 0.0, 1.0);
  out.needs_labels = out.trust < options_.min_trust;
  return out;
}

}  // namespace esdslam
