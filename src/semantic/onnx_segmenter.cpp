#include "semantic/onnx_segmenter.h"

#include <algorithm>
#include <filesystem>
#include <optional>

#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "common/error.h"
#include "common/setting_error.h"
#include "common/timer.h"
#include "semantic/concat_layer.h"
#include "semantic/grouped_conv_layer.h"
#include "semantic/own_layer.h"
#include "semantic/resize_layer.h"
#include "semantic/score_upsampling.h"

namespace esdslam {
namespace {

// The class planes of a 1 x C x H x W blob of that size (copies); none for another shape.
std::vector<cv::Mat> PlanesOf(const cv::Mat& blob, cv::Size size) {
  std::vector<cv::Mat> planes;
  if (blob.dims != 4 || blob.size[0] != 1 || blob.size[2] != size.height || blob.size[3] != size.width) return planes;
  for (int c = 0; c < blob.size[1]; ++c)
    planes.push_back(cv::Mat(size, CV_32F, const_cast<float*>(blob.ptr<float>(0, c))).clone());
  return planes;
}

}  // namespace

void OnnxSegmenterOptions::Check() const {
  if (model_path.empty()) throw Error("Semantic.model: no model path given");
  CheckRange("Semantic.inputWidth", input_width, 32, 4096, "px");
  CheckRange("Semantic.inputHeight", input_height, 32, 4096, "px");
  CheckSetting(input_width % 32 == 0, "Semantic.inputWidth", fmt::format("must be a multiple of 32, got {}", input_width));
  CheckSetting(input_height % 32 == 0, "Semantic.inputHeight",
               fmt::format("must be a multiple of 32, got {}", input_height));
  for (float s : std_rgb)
    if (!(s > 0.0f)) throw Error("segmenter std values must be positive");
  if (class_names.empty() || class_names.size() > 256) throw Error("segmenter needs 1..256 class names");
  if (person_class >= static_cast<int>(class_names.size())) throw Error("person class id out of range");
  CheckRange("Semantic.threads", threads, 0, 256);
}

OnnxSegmenter::OnnxSegmenter(OnnxSegmenterOptions options) : options_(std::move(options)) {
  options_.Check();
  if (!std::filesystem::is_regular_file(options_.model_path))
    throw InputError(options_.model_path, 0, "segmentation model file not found");
  try {
    // This project's layers are registered for this import only (the importer creates every
    // layer). Lock order: Resize, Convolution, Concat.
    std::optional<ScopedLayerConstructor> separable, grouped, strided;  // released in reverse
    if (options_.separable_resize) separable.emplace("Resize", CreateResizeLayer);
    if (options_.own_layers) {
      grouped.emplace("Convolution",
                      options_.portable_kernels ? CreatePortableConvolutionLayer : CreateConvolutionLayer);
      strided.emplace("Concat", CreateConcatLayer);
    }
    net_ = cv::dnn::readNetFromONNX(options_.model_path);
  } catch (const cv::Exception& e) {
    throw InputError(options_.model_path, 0, fmt::format("OpenCV DNN cannot load the ONNX model: {}", e.what()));
  }
  if (net_.empty()) throw InputError(options_.model_path, 0, "OpenCV DNN loaded an empty network");
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  for (const std::string& name : net_.getLayerNames()) {
    const cv::Ptr<cv::dnn::Layer> layer = net_.getLayer(name);
    separable_resize_layers_ += IsSeparableResize(*layer) ? 1 : 0;
    grouped_convolution_layers_ += IsGroupedConvolution(*layer) ? 1 : 0;
    strided_concat_layers_ += IsStridedConcat(*layer) ? 1 : 0;
  }
  if (options_.threads > 0) cv::setNumThreads(options_.threads);
  scores_layer_ = FinalUpsampleInput();
  // A test run checks that the model matches the configured input size and class count.
  Scores(cv::Mat(options_.input_height, options_.input_width, CV_8UC3, cv::Scalar::all(127)));
  spdlog::info("segmenter: {} ({}x{} input, {} classes; own layers: {} Resize, {} grouped convolution, {} Concat)",
               options_.model_path, options_.input_width, options_.input_height, options_.class_names.size(),
               separable_resize_layers_, grouped_convolution_layers_, strided_concat_layers_);
}

std::string OnnxSegmenter::FinalUpsampleInput() {
  const std::vector<int> outputs = net_.getUnconnectedOutLayers();
  if (outputs.size() != 1) return "";
  // The last layer other than an Identity (the ONNX importer names the graph output with one).
  cv::Ptr<cv::dnn::Layer> last = net_.getLayer(outputs[0]);
  std::vector<cv::Ptr<cv::dnn::Layer>> inputs = net_.getLayerInputs(outputs[0]);
  while (last->type == "Identity" && inputs.size() == 1) {
    last = inputs[0];
    inputs = net_.getLayerInputs(net_.getLayerId(last->name));
  }
  if (last->type != "Resize" || inputs.size() != 1) return "";
  const std::string input = inputs[0]->name, output = last->name;
  // Both blobs for a noise image: the shortcut is taken only where it gives the layer's result.
  cv::Mat noise(options_.input_height, options_.input_width, CV_8UC3);
  cv::RNG(1).fill(noise, cv::RNG::UNIFORM, 0, 256);
  std::vector<cv::Mat> blobs;
  try {
    net_.setInput(MakeBlob(noise));
    net_.forward(blobs, std::vector<cv::String>{input, output});
  } catch (const cv::Exception& e) {
    throw InputError(options_.model_path, 0, fmt::format("OpenCV DNN cannot run the model: {}", e.what()));
  }
  const cv::Mat& full = blobs[1];
  if (full.dims != 4 || blobs[0].dims != 4 || full.size[1] != blobs[0].size[1]) return "";
  const std::vector<cv::Mat> ours = UpsampleAlignCorners(blobs[0], cv::Size(full.size[3], full.size[2]));
  double largest_error = 0, largest_score = 0;
  for (int c = 0; c < full.size[1]; ++c) {
    const cv::Mat layer(full.size[2], full.size[3], CV_32F, const_cast<float*>(full.ptr<float>(0, c)));
    largest_error = std::max(largest_error, cv::norm(layer, ours[static_cast<std::size_t>(c)], cv::NORM_INF));
    largest_score = std::max(largest_score, cv::norm(layer, cv::NORM_INF));
  }
  const bool same = largest_error <= 1e-4 * (1.0 + largest_score);
  spdlog::debug("segmenter: final Resize {} upsampled here: {} (largest difference {:.2g})", output,
                same ? "yes" : "no", largest_error);
  return same ? input : "";
}

cv::Mat OnnxSegmenter::MakeBlob(const cv::Mat& bgr) const {
  cv::Mat resized;
  cv::resize(bgr, resized, cv::Size(options_.input_width, options_.input_height), 0, 0, cv::INTER_LINEAR);
  // NCHW float, RGB, /255.
  cv::Mat blob = cv::dnn::blobFromImage(resized, 1.0 / 255.0, cv::Size(), cv::Scalar(), /*swapRB=*/true,
                                        /*crop=*/false, CV_32F);
  for (int c = 0; c < 3; ++c) {
    cv::Mat plane(options_.input_height, options_.input_width, CV_32F, blob.ptr<float>(0, c));
    plane.convertTo(plane, CV_32F, 1.0 / options_.std_rgb[c], -options_.mean_rgb[c] / options_.std_rgb[c]);
  }
  return blob;
}

std::vector<cv::Mat> OnnxSegmenter::Scores(const cv::Mat& bgr) {
  if (bgr.empty() || bgr.type() != CV_8UC3) throw Error("segmenter input must be a non-empty CV_8UC3 BGR image");
  const cv::Mat blob = MakeBlob(bgr);
  const cv::Size input_size(options_.input_width, options_.input_height);
  std::vector<cv::Mat> planes;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    try {
      net_.setInput(blob);
      if (scores_layer_.empty()) {
        planes = PlanesOf(net_.forward(), input_size);
      } else {  // the final upsampling done here (FinalUpsampleInput)
        planes = UpsampleAlignCorners(net_.forward(scores_layer_), input_size);
      }
    } catch (const cv::Exception& e) {
      throw Error(fmt::format("{}: inference failed (does the model take {}x{} inputs?): {}", options_.model_path,
                              options_.input_width, options_.input_height, e.what()));
    }
  }
  const std::size_t num_classes = options_.class_names.size();
  if (planes.size() != num_classes || planes[0].size() != input_size)
    throw Error(fmt::format("{}: expected 1x{}x{}x{} scores from the network", options_.model_path, num_classes,
                            options_.input_height, options_.input_width));
  return planes;
}

std::vector<OnnxSegmenter::LayerTime> OnnxSegmenter::LastLayerTimes() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<double> ticks;
  net_.getPerfProfile(ticks);
  const std::vector<cv::String> names = net_.getLayerNames();  // ids 1..n (0 is the input)
  std::vector<LayerTime> times;
  const double ms_per_tick = 1e3 / cv::getTickFrequency();
  for (std::size_t i = 0; i < ticks.size() && i < names.size(); ++i) {
    const cv::Ptr<cv::dnn::Layer> layer = net_.getLayer(static_cast<int>(i + 1));
    const bool own = dynamic_cast<const OwnLayer*>(layer.get()) != nullptr;
    times.push_back({names[i], layer->type, own, ticks[i] * ms_per_tick});
  }
  return times;
}

SegmentationResult OnnxSegmenter::Segment(const cv::Mat& bgr, double /*timestamp*/) {
  Stopwatch watch;
  std::vector<cv::Mat> scores = Scores(bgr);
  SegmentationResult result;
  const cv::Size image_size = bgr.size();
  if (options_.compute_person_probability && options_.person_class >= 0) {
    cv::resize(SoftmaxProbability(scores, options_.person_class), result.person_probability, image_size, 0, 0,
               cv::INTER_LINEAR);
  }
  const cv::Mat network_labels = ArgmaxLabels(scores);
  if (options_.upsample_scores) {
    result.labels = UpsampledLabels(scores, network_labels, image_size);
  } else {
    cv::resize(network_labels, result.labels, image_size, 0, 0, cv::INTER_NEAREST);
  }
  result.segment_ms = watch.ElapsedMs();
  return result;
}

cv::Mat UpsampledLabels(const std::vector<cv::Mat>& scores, const cv::Mat& network_labels, cv::Size image_size) {
  // Only classes that win somewhere at network resolution compete (typically 2-4 of 21).
  std::array<int, 256> pixels_per_class{};
  for (int y = 0; y < network_labels.rows; ++y) {
    const auto* row = network_labels.ptr<std::uint8_t>(y);
    for (int x = 0; x < network_labels.cols; ++x) ++pixels_per_class[row[x]];
  }
  std::vector<cv::Mat> upsampled;
  std::vector<std::uint8_t> ids;
  for (std::size_t c = 0; c < scores.size(); ++c) {
    if (pixels_per_class[c] == 0) continue;
    upsampled.emplace_back();
    cv::resize(scores[c], upsampled.back(), image_size, 0, 0, cv::INTER_LINEAR);
    ids.push_back(static_cast<std::uint8_t>(c));
  }
  const cv::Mat index = ArgmaxLabels(upsampled);  // index into `ids`
  cv::Mat lut(1, 256, CV_8UC1, cv::Scalar(0));
  for (std::size_t i = 0; i < ids.size(); ++i) lut.at<std::uint8_t>(static_cast<int>(i)) = ids[i];
  cv::Mat labels;
  cv::LUT(index, lut, labels);
  return labels;
}

cv::Mat ArgmaxLabels(const std::vector<cv::Mat>& scores) {
  if (scores.empty() || scores.size() > 256) throw Error("ArgmaxLabels: need 1..256 score planes");
  const cv::Size size = scores[0].size();
  for (const auto& s : scores)
    if (s.type() != CV_32FC1 || s.size() != size) throw Error("ArgmaxLabels: score planes must be CV_32FC1 of one size");
  cv::Mat labels(size, CV_8UC1);
  std::vector<float> best(static_cast<std::size_t>(size.width));
  for (int y = 0; y < size.height; ++y) {
    auto* out = labels.ptr<std::uint8_t>(y);
    const float* first = scores[0].ptr<float>(y);
    std::copy(first, first + size.width, best.begin());
    std::fill(out, out + size.width, 0);
    // Class-major within a row: contiguous, vectorisable loops. Ties keep the lower class id.
    for (std::size_t c = 1; c < scores.size(); ++c) {
      const float* row = scores[c].ptr<float>(y);
      const auto id = static_cast<std::uint8_t>(c);
      for (int x = 0; x < size.width; ++x) {
        const bool better = row[x] > best[static_cast<std::size_t>(x)];
        best[static_cast<std::size_t>(x)] = better ? row[x] : best[static_cast<std::size_t>(x)];
        out[x] = better ? id : out[x];
      }
    }
  }
  return labels;
}

cv::Mat SoftmaxProbability(const std::vector<cv::Mat>& scores, int class_id) {
  cv::Mat max_score = scores[0].clone();
  for (const auto& s : scores) cv::max(max_score, s, max_score);
  cv::Mat sum(max_score.size(), CV_32F, cv::Scalar(0)), e, wanted;
  for (std::size_t c = 0; c < scores.size(); ++c) {
    cv::exp(scores[c] - max_score, e);
    sum += e;
    if (static_cast<int>(c) == class_id) wanted = e.clone();
  }
  return wanted / sum;
}

}  // namespace esdslam
