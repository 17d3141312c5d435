#include "io/tum_sequence.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "common/error.h"
#include "io/associate.h"
#include "io/png_decoder.h"
#include "io/text_lines.h"

namespace esdslam {
namespace fs = std::filesystem;
namespace {

struct ListedImage {
  double timestamp = 0;
  std::string path;  // DIR-joined
};

std::string JoinPath(const std::string& dir, const std::string& relative) {
  return (fs::path(dir) / fs::path(relative)).lexically_normal().string();
}

// rgb.txt / depth.txt: 'timestamp path' per line (extra columns are an error).
std::vector<ListedImage> ReadImageList(const std::string& list_path, const std::string& dir) {
  if (!fs::exists(list_path)) throw InputError(list_path, 0, "image list not found");
  std::vector<ListedImage> images;
  std::vector<double> timestamps;
  std::vector<int> line_numbers;
  for (const TextLine& line : ReadTextLines(list_path)) {
    if (line.fields.size() == 4) {
      throw InputError(list_path, line.line_number,
                       "expected 2 fields 'timestamp path', got 4: this looks like an ORB-SLAM2 association file "
                       "'ts_rgb rgb_path ts_depth depth_path'; pass it with --associations");
    }
    if (line.fields.size() != 2) {
      throw InputError(list_path, line.line_number,
                       fmt::format("expected 2 fields 'timestamp path', got {}", line.fields.size()));
    }
    const double t = ParseFiniteReal(line.fields[0], "timestamp", list_path, line.line_number);
    images.push_back({t, JoinPath(dir, line.fields[1])});
    timestamps.push_back(t);
    line_numbers.push_back(line.line_number);
  }
  CheckStrictlyIncreasing(timestamps, line_numbers, list_path);
  return images;
}

std::vector<FrameEntry> AssociateLists(const std::string& dir, double max_time_difference) {
  const std::vector<ListedImage> rgb = ReadImageList(JoinPath(dir, "rgb.txt"), dir);
  const std::vector<ListedImage> depth = ReadImageList(JoinPath(dir, "depth.txt"), dir);
  std::vector<double> rgb_times, depth_times;
  for (const auto& image : rgb) rgb_times.push_back(image.timestamp);
  for (const auto& image : depth) depth_times.push_back(image.timestamp);
  std::vector<FrameEntry> frames;
  for (const TimestampMatch& m : AssociateTimestamps(rgb_times, depth_times, max_time_difference)) {
    frames.push_back({rgb[m.first].timestamp, rgb[m.first].path, depth[m.second].timestamp, depth[m.second].path});
  }
  spdlog::debug("{}: {} rgb, {} depth, {} associated (|dt| <= {} s)", dir, rgb.size(), depth.size(), frames.size(),
                max_time_difference);
  return frames;
}

// ORB-SLAM2 association file: 'ts_rgb rgb_path ts_depth depth_path'.
std::vector<FrameEntry> ReadAssociationFile(const std::string& path, const std::string& dir) {
  if (!fs::exists(path)) throw InputError(path, 0, "association file not found");
  std::vector<FrameEntry> frames;
  std::vector<double> timestamps;
  std::vector<int> line_numbers;
  for (const TextLine& line : ReadTextLines(path)) {
    if (line.fields.size() != 4) {
      throw InputError(path, line.line_number,
                       fmt::format("expected 4 fields 'ts_rgb rgb_path ts_depth depth_path', got {}",
                                   line.fields.size()));
    }
    FrameEntry frame;
    frame.timestamp = ParseFiniteReal(line.fields[0], "rgb timestamp", path, line.line_number);
    frame.rgb_path = JoinPath(dir, line.fields[1]);
    frame.depth_timestamp = ParseFiniteReal(line.fields[2], "depth timestamp", path, line.line_number);
    frame.depth_path = JoinPath(dir, line.fields[3]);
    frames.push_back(frame);
    timestamps.push_back(frame.timestamp);
    line_numbers.push_back(line.line_number);
  }
  CheckStrictlyIncreasing(timestamps, line_numbers, path);
  return frames;
}

// Drops frames whose images are not on disk; logs (the first few individually) and records them.
std::vector<FrameEntry> DropMissingFiles(std::vector<FrameEntry> frames, std::vector<std::string>& skipped) {
  constexpr std::size_t kMaxIndividualWarnings = 20;
  std::vector<FrameEntry> kept;
  kept.reserve(frames.size());
  for (FrameEntry& frame : frames) {
    bool ok = true;
    for (const std::string* file : {&frame.rgb_path, &frame.depth_path}) {
      if (fs::exists(*file)) continue;
      ok = false;
      skipped.push_back(*file);
      if (skipped.size() <= kMaxIndividualWarnings) {
        spdlog::warn("listed image {} does not exist: frame {:.6f} skipped", *file, frame.timestamp);
      } else {
        spdlog::debug("listed image {} does not exist: frame {:.6f} skipped", *file, frame.timestamp);
      }
    }
    if (ok) kept.push_back(std::move(frame));
  }
  if (skipped.size() > kMaxIndividualWarnings) {
    spdlog::warn("{} listed images are missing in total (the rest are logged at debug level)", skipped.size());
  }
  return kept;
}

}  // namespace

void AssociationOptions::Check() const {
  if (!(max_time_difference > 0)) throw Error("association max_time_difference must be > 0 seconds");
}

std::string DetectAssociationFile(const std::string& dir) {
  if (fs::exists(JoinPath(dir, "rgb.txt")) || fs::exists(JoinPath(dir, "depth.txt"))) return "";
  for (const char* name : {"associations.txt", "association.txt", "associate.txt"}) {
    const std::string path = JoinPath(dir, name);
    if (fs::is_regular_file(path)) return path;
  }
  return "";
}

TumSequence TumSequence::Open(const std::string& dir, const AssociationOptions& options) {
  options.Check();
  if (!fs::is_directory(dir)) throw InputError(dir, 0, "sequence folder not found");
  TumSequence sequence;
  sequence.dir_ = dir;
  std::string association_file = options.association_file;
  if (association_file.empty()) {
    association_file = DetectAssociationFile(dir);
    if (!association_file.empty()) spdlog::info("{}: no rgb.txt/depth.txt, reading {}", dir, association_file);
  }
  std::vector<FrameEntry> frames = association_file.empty() ? AssociateLists(dir, options.max_time_difference)
                                                             : ReadAssociationFile(association_file, dir);
  sequence.frames_ = DropMissingFiles(std::move(frames), sequence.skipped_files_);
  if (sequence.frames_.empty()) {
    throw InputError(dir, 0, "empty sequence: no associated rgb-depth frame with both images present");
  }
  spdlog::info("sequence {}: {} frames", dir, sequence.frames_.size());
  return sequence;
}

bool TumSequence::has_groundtruth() const { return fs::is_regular_file(groundtruth_path()); }

std::string TumSequence::groundtruth_path() const { return JoinPath(dir_, "groundtruth.txt"); }

namespace {

cv::Mat LoadColour(const std::string& path) {
  if (!fs::is_regular_file(path)) throw InputError(path, 0, "colour image not found");
  cv::Mat image = ReadImageUnchanged(path);
  if (image.empty()) throw InputError(path, 0, "cannot decode colour image");
  if (image.depth() != CV_8U) throw InputError(path, 0, "colour image must be 8-bit");
  cv::Mat bgr;
  switch (image.channels()) {
    case 1: cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR); break;
    case 3: bgr = image; break;
    case 4: cv::cvtColor(image, bgr, cv::COLOR_BGRA2BGR); break;
    default: throw InputError(path, 0, "colour image must have 1, 3 or 4 channels");
  }
  return bgr;
}

cv::Mat LoadDepthMetres(const std::string& path, double depth_map_factor) {
  if (!fs::is_regular_file(path)) throw InputError(path, 0, "depth image not found");
  const cv::Mat raw = ReadImageUnchanged(path);
  if (raw.empty()) throw InputError(path, 0, "cannot decode depth image");
  if (raw.type() != CV_16UC1) throw InputError(path, 0, "depth image must be 16-bit single channel");
  cv::Mat depth_m;
  raw.convertTo(depth_m, CV_32F, 1.0 / depth_map_factor);  // 0 stays 0 (invalid)
  return depth_m;
}

}  // namespace

RgbdImages LoadRgbd(const FrameEntry& frame, double depth_map_factor) {
  if (!(depth_map_factor > 0)) throw Error("depth_map_factor must be > 0");
  RgbdImages images;
  images.bgr = LoadColour(frame.rgb_path);
  images.depth_m = LoadDepthMetres(frame.depth_path, depth_map_factor);
  if (images.bgr.size() != images.depth_m.size()) {
    throw InputError(frame.depth_path, 0,
                     fmt::format("depth size {}x{} differs from colour image {} ({}x{})", images.depth_m.cols,
                                 images.depth_m.rows, frame.rgb_path, images.bgr.cols, images.bgr.rows));
  }
  return images;
}

const FrameEntry* NearestFrame(const std::vector<FrameEntry>& frames, double timestamp, double max_dt) {
  const auto it = std::lower_bound(frames.begin(), frames.end(), timestamp,
                                   [](const FrameEntry& f, double t) { return f.timestamp < t; });
  const FrameEntry* best = nullptr;
  double best_dt = max_dt;
  for (auto candidate : {it, it == frames.begin() ? it : std::prev(it)}) {
    if (candidate == frames.end()) continue;
    const double dt = std::abs(candidate->timestamp - timestamp);
    if (dt <= best_dt) {
      best_dt = dt;
      best = &*candidate;
    }
  }
  return best;
}

}  // namespace esdslam
