#include "semantic/folder_segmenter.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "common/error.h"
#include "common/setting_error.h"
#include "common/timer.h"

namespace esdslam {
namespace fs = std::filesystem;

void FolderSegmenterOptions::Check() const {
  if (folder.empty()) throw Error("Semantic.maskFolder: no folder given");
  CheckRange("Semantic.maskTolerance", tolerance_s, 0.0, 10.0, "s");
}

FolderSegmenter::FolderSegmenter(FolderSegmenterOptions options) : options_(std::move(options)) {
  options_.Check();
  if (!fs::is_directory(options_.folder)) throw InputError(options_.folder, 0, "mask folder not found");
  for (const auto& entry : fs::directory_iterator(options_.folder)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".png") continue;
    const std::string stem = entry.path().stem().string();
    char* end = nullptr;
    const double t = std::strtod(stem.c_str(), &end);
    if (end == stem.c_str() || *end != '\0' || !std::isfinite(t)) continue;  // not <timestamp>.png
    masks_.push_back({t, entry.path().string()});
  }
  if (masks_.empty()) throw InputError(options_.folder, 0, "no <timestamp>.png mask files in the folder");
  std::sort(masks_.begin(), masks_.end(), [](const MaskFile& a, const MaskFile& b) { return a.timestamp < b.timestamp; });
  spdlog::info("segmenter: {} precomputed masks in {}", masks_.size(), options_.folder);
}

const FolderSegmenter::MaskFile* FolderSegmenter::Find(double timestamp) const {
  const auto after = std::lower_bound(masks_.begin(), masks_.end(), timestamp,
                                      [](const MaskFile& m, double t) { return m.timestamp < t; });
  const MaskFile* best = nullptr;
  if (after != masks_.end()) best = &*after;
  if (after != masks_.begin()) {
    const MaskFile* before = &*(after - 1);
    if (!best || timestamp - before->timestamp <= best->timestamp - timestamp) best = before;
  }
  if (best && std::abs(best->timestamp - timestamp) <= options_.tolerance_s) return best;
  return nullptr;
}

SegmentationResult FolderSegmenter::Segment(const cv::Mat& bgr, double timestamp) {
  Stopwatch watch;
  if (bgr.empty()) throw Error("FolderSegmenter: empty input image");
  SegmentationResult result;
  const MaskFile* mask = Find(timestamp);
  if (!mask) {
    if (!options_.allow_missing)
      throw InputError(options_.folder, 0,
                       fmt::format("no mask <timestamp>.png within {} s of frame timestamp {:.6f} "
                                   "(set Semantic.allowMissingMasks to treat such frames as all background)",
                                   options_.tolerance_s, timestamp));
    spdlog::warn("segmenter: no mask for timestamp {:.6f} in {}, using background", timestamp, options_.folder);
    result.labels = cv::Mat(bgr.size(), CV_8UC1, cv::Scalar(0));
  } else {
    cv::Mat labels = cv::imread(mask->path, cv::IMREAD_UNCHANGED);
    if (labels.empty()) throw InputError(mask->path, 0, "cannot read mask image");
    if (labels.type() != CV_8UC1) throw InputError(mask->path, 0, "mask must be a single-channel 8-bit PNG of class ids");
    if (labels.size() != bgr.size()) cv::resize(labels, labels, bgr.size(), 0, 0, cv::INTER_NEAREST);
    result.labels = labels;
  }
  result.segment_ms = watch.ElapsedMs();
  return result;
}

}  // namespace esdslam
