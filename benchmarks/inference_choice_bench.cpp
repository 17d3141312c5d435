// Cheaper inference (issue 12, item 4): time and accuracy of each network configuration.
//
//   inference_choice_bench [--model FILE:WxH]... [--crop FILE:WxH]... [--int8 FILE:WxH]... [--threads 1,2]
//                          [--resize separable,opencv] [--resize-ab FILE:WxH]... [--layers-ab FILE:WxH]...
//                          [--rounds N] [--profile FILE:WxH]... [--kernels-ab FILE:WxH]...
//                          [--sequence DIR] [--labels DIR] [--step N] [--crop-lag N] [--crop-margin PX]
//
// For every model and OpenCV thread count: CPU time of the process per Segment() call (resize,
// network, score upsampling, argmax; the process runs nothing else, so this is the cost on the
// cores), wall time per call (noisy on a shared machine), and accuracy of the person labels at
// image resolution on every N-th frame of the sequence against the 384x384 model (the training
// resolution, checked against the original network by EspNetV2Reference): mean person IoU over
// the frames where either has a person, pooled person recall; and the agreement of all labels with
// the six reference label maps of the original network (../shared/models/espnetv2/reference,
// 384x384 maps resized to 640x480, nearest).
// --crop: the model runs on the bounding box of the people labelled --crop-lag frames earlier (the
// labels in --labels DIR, e.g. /work/cache/labels/<seq>, as a stand-in for the predicted people),
// grown by --crop-margin pixels and to the model's aspect ratio; the rest of the frame is labelled
// background; frames without people there run on the whole frame. The mean crop area is printed.
// --int8: the model quantised by OpenCV DNN itself (cv::dnn::Net::quantize: int8 weights per
// channel and activations calibrated on one frame, the middle of the sequence: the ESPNetv2
// graph's reshapes are fixed to batch 1, so the calibration batch is one frame); CPU time of the
// network alone (one OpenCV thread) against the float network, and agreement of the argmax labels
// with the float network at network resolution on the frames above.
// --resize: which Resize layers the network runs with, each in turn for every model and thread
// count: "separable" (OnnxSegmenter's default, semantic/resize_layer.h) and/or "opencv" (OpenCV
// DNN's own layer).
// --resize-ab: the model twice, with OpenCV's and the separable Resize, one OpenCV thread, calls
// interleaved frame by frame (which goes first alternates) for --rounds passes over the frames, so
// that both see the same machine load: CPU time of the calling thread per Segment() call (median
// and mean), and the pixels whose labels differ. Only this table is printed when given alone.
// --layers-ab: the same for the grouped convolution and strided Concat layers
// (semantic/grouped_conv_layer.h, semantic/concat_layer.h) against OpenCV's, both with the
// separable Resize.
// --kernels-ab: the same for the grouped convolution's portable inner loops against the ones the
// CPU runs best (semantic/conv_kernels.h: AVX2+FMA where available).
// --profile: the model (this project's layers, one OpenCV thread) on every frame, --rounds
// passes: wall ms per call of each layer type and of the 15 slowest layers (OpenCV's per-layer
// profile; fused layers show 0). Only this table is printed when given alone.
// Defaults: the three committed models, threads 1 and 2, separable Resize, ../shared/data/bonn_crowd_dev,
// step 10.
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/dnn.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/timer.h"
#include "io/tum_sequence.h"
#include "semantic/conv_kernels.h"
#include "semantic/onnx_segmenter.h"

namespace esdslam::bench {
namespace {
namespace fs = std::filesystem;

constexpr int kPerson = 15;

double ProcessCpuMs() {
  timespec now;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return 1e3 * static_cast<double>(now.tv_sec) + 1e-6 * static_cast<double>(now.tv_nsec);
}

struct ModelSpec {
  std::string path;
  int width = 0, height = 0;
  std::string Name() const { return fs::path(path).filename().string(); }
};

ModelSpec ParseModel(const std::string& spec) {
  const std::size_t colon = spec.rfind(':'), x = spec.rfind('x');
  if (colon == std::string::npos || x == std::string::npos || x < colon)
    throw Error("--model/--crop: expected FILE:WIDTHxHEIGHT, got " + spec);
  return {spec.substr(0, colon), std::stoi(spec.substr(colon + 1, x - colon - 1)), std::stoi(spec.substr(x + 1))};
}

struct Args {
  std::vector<ModelSpec> models, crops, int8, resize_ab, layers_ab, profile, kernels_ab;
  std::vector<int> threads{1, 2};
  std::vector<std::string> resize{"separable"};
  std::string sequence = std::string(ESDSLAM_TEST_DATA_DIR) + "/data/bonn_crowd_dev";
  std::string labels = "/work/cache/labels/bonn_crowd_dev";
  int step = 10, crop_lag = 5, crop_margin = 48, rounds = 2;
};

std::unique_ptr<OnnxSegmenter> MakeSegmenter(const ModelSpec& model, int threads, bool separable_resize = true,
                                             bool own_layers = true, bool portable_kernels = false) {
  OnnxSegmenterOptions options;
  options.portable_kernels = portable_kernels;
  options.separable_resize = separable_resize;
  options.own_layers = own_layers;
  options.model_path = model.path;
  options.input_width = model.width;
  options.input_height = model.height;
  options.threads = threads;
  options.compute_person_probability = false;
  return std::make_unique<OnnxSegmenter>(options);
}

struct Frame {
  cv::Mat bgr;
  cv::Mat earlier_person;  // person mask of the labels crop_lag frames before (may be empty)
};

// The crop for `model` around `people` (CV_8U), or an empty rect for the whole frame.
cv::Rect CropAround(const cv::Mat& people, const ModelSpec& model, int margin) {
  if (people.empty() || cv::countNonZero(people) == 0) return {};
  const cv::Rect image(0, 0, people.cols, people.rows);
  cv::Rect box = cv::boundingRect(people);
  box = cv::Rect(box.x - margin, box.y - margin, box.width + 2 * margin, box.height + 2 * margin) & image;
  const double aspect = static_cast<double>(model.width) / model.height;
  int w = box.width, h = box.height;
  if (w < aspect * h) w = static_cast<int>(std::ceil(aspect * h)); else h = static_cast<int>(std::ceil(w / aspect));
  w = std::min(w, image.width);
  h = std::min(h, image.height);
  const int cx = box.x + box.width / 2, cy = box.y + box.height / 2;
  const int x = std::clamp(cx - w / 2, 0, image.width - w), y = std::clamp(cy - h / 2, 0, image.height - h);
  return cv::Rect(x, y, w, h);
}

cv::Mat SegmentMaybeCropped(OnnxSegmenter& segmenter, const cv::Mat& bgr, const cv::Rect& crop) {
  if (crop.empty()) return segmenter.Segment(bgr, 0.0).labels;
  cv::Mat labels = cv::Mat::zeros(bgr.size(), CV_8U);
  segmenter.Segment(bgr(crop).clone(), 0.0).labels.copyTo(labels(crop));
  return labels;
}

struct Score {
  double cpu_ms = 0, wall_ms = 0, iou = 0, truth_px = 0, covered_px = 0, crop_area = 0;
  int calls = 0, iou_frames = 0;
};

Score Evaluate(OnnxSegmenter& segmenter, const ModelSpec& model, const std::vector<Frame>& frames,
               const std::vector<cv::Mat>& reference, bool crop, int margin) {
  Score score;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const cv::Rect box = crop ? CropAround(frames[i].earlier_person, model, margin) : cv::Rect();
    const double cpu0 = ProcessCpuMs();
    Stopwatch wall;
    const cv::Mat labels = SegmentMaybeCropped(segmenter, frames[i].bgr, box);
    score.wall_ms += wall.ElapsedMs();
    score.cpu_ms += ProcessCpuMs() - cpu0;
    ++score.calls;
    score.crop_area += box.empty() ? 1.0 : static_cast<double>(box.area()) / static_cast<double>(labels.total());
    if (reference.empty()) continue;
    const cv::Mat person = labels == kPerson, truth = reference[i] == kPerson;
    const int uni = cv::countNonZero(person | truth);
    if (uni > 0) {
      score.iou += cv::countNonZero(person & truth) / static_cast<double>(uni);
      ++score.iou_frames;
    }
    score.truth_px += cv::countNonZero(truth);
    score.covered_px += cv::countNonZero(truth & person);
  }
  return score;
}

// Share of pixels whose labels agree with the original network's 384x384 maps (resized, nearest).
double ReferenceAgreement(OnnxSegmenter& segmenter) {
  const fs::path dir = fs::path(ESDSLAM_TEST_DATA_DIR) / "models" / "espnetv2" / "reference";
  if (!fs::is_directory(dir)) return -1;
  double agree = 0, total = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.size() < 12 || name.substr(name.size() - 11) != ".labels.png") continue;
    const std::string stem = (dir / name.substr(0, name.size() - 11)).string();
    const cv::Mat bgr = cv::imread(stem + ".png", cv::IMREAD_COLOR);
    cv::Mat reference = cv::imread(stem + ".labels.png", cv::IMREAD_UNCHANGED);
    cv::resize(reference, reference, bgr.size(), 0, 0, cv::INTER_NEAREST);
    agree += cv::countNonZero(segmenter.Segment(bgr, 0.0).labels == reference);
    total += static_cast<double>(reference.total());
  }
  return total > 0 ? agree / total : -1;
}

std::vector<Frame> LoadFrames(const Args& args) {
  const TumSequence sequence = TumSequence::Open(args.sequence);
  std::vector<Frame> frames;
  const auto& entries = sequence.frames();
  for (std::size_t i = 0; i < entries.size(); i += static_cast<std::size_t>(args.step)) {
    Frame frame{cv::imread(entries[i].rgb_path, cv::IMREAD_COLOR), cv::Mat()};
    if (i >= static_cast<std::size_t>(args.crop_lag)) {
      const std::string earlier = fs::path(entries[i - static_cast<std::size_t>(args.crop_lag)].rgb_path).filename().string();
      const cv::Mat labels = cv::imread(args.labels + "/" + earlier, cv::IMREAD_UNCHANGED);
      if (!labels.empty()) frame.earlier_person = labels == kPerson;
    }
    frames.push_back(frame);
  }
  return frames;
}

// The network input of OnnxSegmenter (bilinear resize, RGB, /255, ImageNet mean and std).
cv::Mat NetworkInput(const cv::Mat& bgr, const ModelSpec& model) {
  cv::Mat rgb;
  cv::resize(bgr, rgb, cv::Size(model.width, model.height), 0, 0, cv::INTER_LINEAR);
  cv::cvtColor(rgb, rgb, cv::COLOR_BGR2RGB);
  rgb.convertTo(rgb, CV_32F, 1.0 / 255.0);
  rgb -= cv::Scalar(0.485, 0.456, 0.406);
  cv::divide(rgb, cv::Scalar(0.229, 0.224, 0.225), rgb);
  return cv::dnn::blobFromImage(rgb);
}

// Argmax over the class axis of a 1 x C x H x W score blob.
cv::Mat Argmax(const cv::Mat& scores) {
  const int classes = scores.size[1], h = scores.size[2], w = scores.size[3];
  cv::Mat labels(h, w, CV_8U), best(h, w, CV_32F, cv::Scalar(-1e30));
  for (int c = 0; c < classes; ++c) {
    const cv::Mat plane(h, w, CV_32F, const_cast<float*>(scores.ptr<float>(0, c)));
    const cv::Mat better = plane > best;
    plane.copyTo(best, better);
    labels.setTo(c, better);
  }
  return labels;
}

void ReportInt8(const ModelSpec& model, const std::vector<Frame>& frames) {
  cv::setNumThreads(1);
  cv::dnn::Net net = cv::dnn::readNetFromONNX(model.path);
  cv::dnn::Net quantised = net.quantize(std::vector<cv::Mat>{NetworkInput(frames[frames.size() / 2].bgr, model)}, CV_32F, CV_32F);
  double float_ms = 0, int8_ms = 0, agree = 0, person_iou = 0;
  int person_frames = 0;
  for (const Frame& frame : frames) {
    const cv::Mat input = NetworkInput(frame.bgr, model);
    double cpu0 = ProcessCpuMs();
    net.setInput(input);
    const cv::Mat reference = Argmax(net.forward());
    float_ms += ProcessCpuMs() - cpu0;
    cpu0 = ProcessCpuMs();
    quantised.setInput(input);
    const cv::Mat labels = Argmax(quantised.forward());
    int8_ms += ProcessCpuMs() - cpu0;
    agree += cv::countNonZero(labels == reference) / static_cast<double>(labels.total());
    const int uni = cv::countNonZero((labels == kPerson) | (reference == kPerson));
    if (uni > 0) {
      person_iou += cv::countNonZero((labels == kPerson) & (reference == kPerson)) / static_cast<double>(uni);
      ++person_frames;
    }
  }
  const double n = static_cast<double>(frames.size());
  std::printf("| %s | %dx%d | %.1f | %.1f | %.4f | %.3f |\n", model.Name().c_str(), model.width, model.height,
              float_ms / n, int8_ms / n, agree / n, person_iou / std::max(1, person_frames));
  std::fflush(stdout);
}

// Median and mean of `values` (not empty).
std::pair<double, double> MedianAndMean(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  double sum = 0;
  for (double v : values) sum += v;
  return {values[values.size() / 2], sum / static_cast<double>(values.size())};
}

// What an A/B compares: OpenCV's Resize layers against the separable one, OpenCV's grouped
// convolution and Concat against this project's, or the grouped convolution's portable inner
// loops against the AVX2+FMA ones.
enum class AbKind { kResize, kLayers, kKernels };

// A/B of segmenter 0 (OpenCV's layers, or the portable loops) against segmenter 1 (all of this
// project's layers with the best loops).
void ReportAb(const ModelSpec& model, const std::vector<Frame>& frames, int rounds, AbKind kind) {
  std::unique_ptr<OnnxSegmenter> segmenters[2] = {
      MakeSegmenter(model, 1, kind != AbKind::kResize, kind != AbKind::kLayers, kind == AbKind::kKernels),
      MakeSegmenter(model, 1, true, true)};
  for (auto& segmenter : segmenters) segmenter->Segment(frames.front().bgr, 0.0);  // warm-up
  std::vector<double> cpu_ms[2];
  double differing = 0, pixels = 0;
  for (int round = 0; round < rounds; ++round) {
    for (std::size_t i = 0; i < frames.size(); ++i) {
      cv::Mat labels[2];
      const std::size_t first = (i + static_cast<std::size_t>(round)) % 2;
      for (std::size_t k : {first, 1 - first}) {
        ThreadCpuStopwatch watch;
        labels[k] = segmenters[k]->Segment(frames[i].bgr, 0.0).labels;
        cpu_ms[k].push_back(watch.ElapsedMs());
      }
      differing += cv::countNonZero(labels[0] != labels[1]);
      pixels += static_cast<double>(labels[0].total());
    }
  }
  const auto [opencv_median, opencv_mean] = MedianAndMean(cpu_ms[0]);
  const auto [separable_median, separable_mean] = MedianAndMean(cpu_ms[1]);
  std::printf("| %s | %dx%d | %zu | %.1f | %.1f | %.1f | %.1f | %.0f of %.0f |\n", model.Name().c_str(), model.width,
              model.height, cpu_ms[0].size(), opencv_median, separable_median, opencv_mean, separable_mean, differing,
              pixels);
  std::fflush(stdout);
}

// Per-layer wall time of `model` over `rounds` passes over `frames` (see --profile).
void ReportProfile(const ModelSpec& model, const std::vector<Frame>& frames, int rounds) {
  std::unique_ptr<OnnxSegmenter> segmenter = MakeSegmenter(model, 1, true, true);
  segmenter->Segment(frames.front().bgr, 0.0);  // warm-up
  std::vector<OnnxSegmenter::LayerTime> sums;
  int calls = 0;
  double cpu_ms = 0;
  for (int round = 0; round < rounds; ++round) {
    for (const Frame& frame : frames) {
      ThreadCpuStopwatch watch;
      segmenter->Segment(frame.bgr, 0.0);
      cpu_ms += watch.ElapsedMs();
      const std::vector<OnnxSegmenter::LayerTime> times = segmenter->LastLayerTimes();
      if (sums.empty()) sums = times;
      else for (std::size_t i = 0; i < times.size() && i < sums.size(); ++i) sums[i].ms += times[i].ms;
      ++calls;
    }
  }
  std::vector<std::pair<std::string, std::pair<int, double>>> by_type;
  double total = 0;
  for (const auto& layer : sums) {
    total += layer.ms;
    const std::string type = layer.type + (layer.own ? " (own)" : "");
    auto it = std::find_if(by_type.begin(), by_type.end(), [&](const auto& t) { return t.first == type; });
    if (it == by_type.end()) by_type.push_back({type, {1, layer.ms}});
    else { ++it->second.first; it->second.second += layer.ms; }
  }
  std::sort(by_type.begin(), by_type.end(), [](const auto& a, const auto& b) { return a.second.second > b.second.second; });
  std::printf("%s, %d calls: CPU %.1f ms per Segment() call, layers' wall %.1f ms per call\n\n| layer type | layers | "
              "ms per call |\n|---|---|---|\n", model.Name().c_str(), calls, cpu_ms / calls, total / calls);
  for (const auto& [type, count_ms] : by_type)
    std::printf("| %s | %d | %.2f |\n", type.c_str(), count_ms.first, count_ms.second / calls);
  std::sort(sums.begin(), sums.end(), [](const auto& a, const auto& b) { return a.ms > b.ms; });
  std::printf("\n| slowest layers | type | ms per call |\n|---|---|---|\n");
  for (std::size_t i = 0; i < sums.size() && i < 15; ++i)
    std::printf("| %s | %s%s | %.2f |\n", sums[i].name.c_str(), sums[i].type.c_str(), sums[i].own ? " (own)" : "",
                sums[i].ms / calls);
  std::fflush(stdout);
}

void Run(const Args& args) {
  const std::vector<Frame> frames = LoadFrames(args);
  if (!args.kernels_ab.empty()) {
    std::printf("Grouped convolution's inner loops, portable against %s, 1 thread, calls interleaved: CPU ms of the "
                "calling thread per Segment() call\n\n| model | input | calls each | portable median | best median | "
                "portable mean | best mean | label pixels differing |\n|---|---|---|---|---|---|---|---|\n",
                BestConvKernels().name);
    for (const ModelSpec& model : args.kernels_ab) ReportAb(model, frames, args.rounds, AbKind::kKernels);
    if (args.models.empty() && args.crops.empty() && args.int8.empty() && args.layers_ab.empty() &&
        args.resize_ab.empty() && args.profile.empty())
      return;
  }
  if (!args.profile.empty()) {
    for (const ModelSpec& model : args.profile) ReportProfile(model, frames, args.rounds);
    if (args.models.empty() && args.crops.empty() && args.int8.empty() && args.layers_ab.empty() &&
        args.resize_ab.empty())
      return;
  }
  if (!args.resize_ab.empty()) {
    std::printf("Resize layers, OpenCV's against separable, 1 thread, calls interleaved: CPU ms of the calling thread "
                "per Segment() call\n\n| model | input | calls each | OpenCV median | separable median | OpenCV mean | "
                "separable mean | label pixels differing |\n|---|---|---|---|---|---|---|---|\n");
    for (const ModelSpec& model : args.resize_ab) ReportAb(model, frames, args.rounds, AbKind::kResize);
    if (args.models.empty() && args.crops.empty() && args.int8.empty() && args.layers_ab.empty()) return;
    std::printf("\n");
  }
  if (!args.layers_ab.empty()) {
    std::printf("Grouped convolution and Concat layers, OpenCV's against this project's, 1 thread, calls interleaved: "
                "CPU ms of the calling thread per Segment() call\n\n| model | input | calls each | OpenCV median | own "
                "median | OpenCV mean | own mean | label pixels differing |\n|---|---|---|---|---|---|---|---|\n");
    for (const ModelSpec& model : args.layers_ab) ReportAb(model, frames, args.rounds, AbKind::kLayers);
    if (args.models.empty() && args.crops.empty() && args.int8.empty()) return;
    std::printf("\n");
  }
  const ModelSpec reference_model{std::string(ESDSLAM_SOURCE_DIR) + "/models/espnetv2_s2.0_voc_384x384.onnx", 384, 384};
  std::vector<cv::Mat> reference;
  {
    auto segmenter = MakeSegmenter(reference_model, 2);
    for (const Frame& frame : frames) reference.push_back(segmenter->Segment(frame.bgr, 0.0).labels);
  }
  std::printf("%zu frames of %s (every %d-th); accuracy against %s on them\n\n", frames.size(), args.sequence.c_str(),
              args.step, reference_model.Name().c_str());
  std::printf("| model | input | crop | resize | threads | CPU ms / call | wall ms / call | person IoU | "
              "person recall | labels = reference frames | crop area |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
  auto report = [&](const ModelSpec& model, bool crop) {
    for (int threads : args.threads) for (const std::string& resize : args.resize) {
      auto segmenter = MakeSegmenter(model, threads, resize == "separable");
      segmenter->Segment(frames.front().bgr, 0.0);  // warm-up
      const Score s = Evaluate(*segmenter, model, frames, reference, crop, args.crop_margin);
      const double agreement = crop ? -1 : ReferenceAgreement(*segmenter);
      std::printf("| %s | %dx%d | %s | %s | %d | %.1f | %.1f | %.3f | %.3f | %s | %.2f |\n", model.Name().c_str(),
                  model.width, model.height, crop ? "yes" : "no", resize.c_str(), threads, s.cpu_ms / s.calls,
                  s.wall_ms / s.calls,
                  s.iou / std::max(1, s.iou_frames), s.covered_px / std::max(1.0, s.truth_px),
                  agreement < 0 ? "-" : cv::format("%.4f", agreement).c_str(), s.crop_area / s.calls);
      std::fflush(stdout);
    }
  };
  for (const ModelSpec& model : args.models) report(model, false);
  for (const ModelSpec& model : args.crops) report(model, true);
  if (args.int8.empty()) return;
  std::printf("\nint8 (cv::dnn::Net::quantize) against the float network, one thread, network only\n\n"
              "| model | input | float CPU ms | int8 CPU ms | labels agree | person IoU |\n|---|---|---|---|---|---|\n");
  for (const ModelSpec& model : args.int8) ReportInt8(model, frames);
}

Args Parse(int argc, char** argv) {
  Args args;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) throw Error("missing value after " + flag);
    const std::string value = argv[++i];
    if (flag == "--model") args.models.push_back(ParseModel(value));
    else if (flag == "--crop") args.crops.push_back(ParseModel(value));
    else if (flag == "--int8") args.int8.push_back(ParseModel(value));
    else if (flag == "--resize-ab") args.resize_ab.push_back(ParseModel(value));
    else if (flag == "--layers-ab") args.layers_ab.push_back(ParseModel(value));
    else if (flag == "--profile") args.profile.push_back(ParseModel(value));
    else if (flag == "--kernels-ab") args.kernels_ab.push_back(ParseModel(value));
    else if (flag == "--rounds") args.rounds = std::stoi(value);
    else if (flag == "--sequence") args.sequence = value;
    else if (flag == "--labels") args.labels = value;
    else if (flag == "--step") args.step = std::stoi(value);
    else if (flag == "--crop-lag") args.crop_lag = std::stoi(value);
    else if (flag == "--crop-margin") args.crop_margin = std::stoi(value);
    else if (flag == "--resize") {
      args.resize.clear();
      std::stringstream list(value);
      for (std::string r; std::getline(list, r, ',');) {
        if (r != "separable" && r != "opencv") throw Error("--resize: separable or opencv, got " + r);
        args.resize.push_back(r);
      }
    } else if (flag == "--threads") {
      args.threads.clear();
      std::stringstream list(value);
      for (std::string t; std::getline(list, t, ',');) args.threads.push_back(std::stoi(t));
    } else {
      throw Error("unknown flag " + flag);
    }
  }
  if (args.models.empty() && args.crops.empty() && args.int8.empty() && args.resize_ab.empty() &&
      args.layers_ab.empty() && args.profile.empty() && args.kernels_ab.empty()) {
    const std::string dir = std::string(ESDSLAM_SOURCE_DIR) + "/models/";
    args.models = {{dir + "espnetv2_s2.0_voc_256x192.onnx", 256, 192},
                   {dir + "espnetv2_s2.0_voc_384x288.onnx", 384, 288},
                   {dir + "espnetv2_s2.0_voc_384x384.onnx", 384, 384}};
  }
  if (args.step < 1 || args.crop_lag < 0 || args.crop_margin < 0 || args.rounds < 1)
    throw Error("--step, --rounds >= 1, --crop-lag, --crop-margin >= 0");
  return args;
}

}  // namespace
}  // namespace esdslam::bench

int main(int argc, char** argv) {
  try {
    esdslam::bench::Run(esdslam::bench::Parse(argc, argv));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "inference_choice_bench: %s\n", e.what());
    return 1;
  }
}
