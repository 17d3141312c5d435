#pragma once
// Segmentation with an ONNX network on OpenCV DNN (CPU). The shipped models are ESPNetv2 for
// PASCAL VOC (models/espnetv2_s2.0_voc_<W>x<H>.onnx, see tools/espnetv2/README.md).
//
// Pipeline per frame: resize the whole frame to the network input (bilinear, cv::resize on
// 8 bits), BGR->RGB, /255, (x - mean) / std, run, then
//   upsample_scores = true  (default): resize the class-score planes bilinearly to the image
//                          size and take the argmax per pixel (smooth, sub-input-pixel borders).
//                          Only classes that win at least one pixel at network resolution take
//                          part (a class that wins nowhere could at most win a sliver along a
//                          border between two others); this cuts the cost from 21 planes to the
//                          2-4 classes a frame typically holds;
//   upsample_scores = false: argmax at network resolution, labels resized with nearest neighbour
//                          (faster, blocky borders).
// The person probability (softmax of the person class) is computed at network resolution and
// resized bilinearly to the image size.
// A network that ends with a bilinear align-corners Resize to its input size (ESPNetv2) is run
// up to that layer's input; the upsampling is done by UpsampleAlignCorners
// (semantic/score_upsampling.h): the same scores, about 10 % of the network time less at 256x192.
// The network's other bilinear Resize layers (the decoder's) run as the separable layer of
// semantic/resize_layer.h (separable_resize); its depthwise and small grouped convolutions as
// the layer of semantic/grouped_conv_layer.h, its Concat layers along height or width as the one
// of semantic/concat_layer.h (own_layers). Both give the same scores up to float rounding (the
// labels of the reference images are unchanged) in about 70 % of OpenCV's time at 256x192.

#include <array>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>

#include "semantic/segmenter.h"

namespace esdslam {

struct OnnxSegmenterOptions {
  std::string model_path;  // Semantic.model (already resolved; see ResolveModelPath)
  int input_width = 384;   // Semantic.inputWidth: the width the model was exported for (px)
  int input_height = 288;  // Semantic.inputHeight
  std::array<float, 3> mean_rgb{0.485f, 0.456f, 0.406f};  // of the /255 input, RGB order
  std::array<float, 3> std_rgb{0.229f, 0.224f, 0.225f};
  std::vector<std::string> class_names = VocClassNames();
  int person_class = kVocPersonClass;  // -1: no person probability
  bool compute_person_probability = true;
  bool upsample_scores = true;
  // Load the model's bilinear Resize layers as the separable layer (semantic/resize_layer.h)
  // instead of OpenCV's own; false: OpenCV's layers throughout (for comparisons).
  bool separable_resize = true;
  // Load the grouped convolutions with few inputs per group and the Concat layers along height or
  // width as this project's layers (semantic/grouped_conv_layer.h, semantic/concat_layer.h);
  // false: OpenCV's (for comparisons).
  bool own_layers = true;
  // The grouped convolution with its portable inner loops even where the CPU has AVX2+FMA
  // (semantic/conv_kernels.h; for comparisons).
  bool portable_kernels = false;
  // Semantic.threads: > 0 calls cv::setNumThreads(threads) when the segmenter is created. Note
  // that OpenCV's thread count is process-wide. 0 leaves OpenCV's setting untouched.
  int threads = 0;

  void Check() const;
};

class OnnxSegmenter : public Segmenter {
 public:
  // Loads the model; throws Error if the file is missing or OpenCV cannot import it, or if a
  // test run does not give num_classes x input_height x input_width scores.
  explicit OnnxSegmenter(OnnxSegmenterOptions options);

  SegmentationResult Segment(const cv::Mat& bgr, double timestamp) override;
  std::string Name() const override { return "onnx:" + options_.model_path; }

  // Network output for `bgr`: one CV_32FC1 score plane per class at network resolution.
  std::vector<cv::Mat> Scores(const cv::Mat& bgr);

  const OnnxSegmenterOptions& options() const { return options_; }
  // True when the final Resize is done by UpsampleAlignCorners (see scores_layer_).
  bool upsamples_scores_itself() const { return !scores_layer_.empty(); }
  // How many of the network's layers are the separable Resize (0 without separable_resize).
  int separable_resize_layers() const { return separable_resize_layers_; }
  // How many are the grouped convolution and the strided Concat (0 without own_layers).
  int grouped_convolution_layers() const { return grouped_convolution_layers_; }
  int strided_concat_layers() const { return strided_concat_layers_; }

  // Time per layer of the last Scores()/Segment() call (OpenCV's cv::dnn::Net::getPerfProfile:
  // wall ms of each layer's forward, in the net's order); for profiling benchmarks.
  struct LayerTime {
    std::string name, type;
    bool own = false;  // one of this project's layers (semantic/own_layer.h)
    double ms = 0;
  };
  std::vector<LayerTime> LastLayerTimes();

 private:
  cv::Mat MakeBlob(const cv::Mat& bgr) const;
  std::string FinalUpsampleInput();


  OnnxSegmenterOptions options_;
  std::mutex mutex_;  // cv::dnn::Net::forward is not re-entrant
  cv::dnn::Net net_;
  // The scores are taken from this layer and upsampled by UpsampleAlignCorners when the network
  // ends with a Resize that it reproduces (checked on a noise image at load); empty: the
  // network's output as it is.
  std::string scores_layer_;
  int separable_resize_layers_ = 0;
  int grouped_convolution_layers_ = 0;
  int strided_concat_layers_ = 0;
};

// Argmax over score planes (all the same size, CV_32FC1) -> CV_8UC1 labels.
cv::Mat ArgmaxLabels(const std::vector<cv::Mat>& scores);
// Labels at `image_size` from network-resolution scores and their argmax `network_labels`
// (see upsample_scores above).
cv::Mat UpsampledLabels(const std::vector<cv::Mat>& scores, const cv::Mat& network_labels, cv::Size image_size);
// Softmax probability of class `class_id` -> CV_32FC1.
cv::Mat SoftmaxProbability(const std::vector<cv::Mat>& scores, int class_id);

}  // namespace esdslam
