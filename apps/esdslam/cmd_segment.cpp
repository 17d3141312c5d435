// esdslam segment: label images with the configured segmenter (see src/semantic).
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <spdlog/spdlog.h>

#include "apps/esdslam/commands.h"
#include "common/error.h"
#include "semantic/class_groups.h"
#include "semantic/overlay.h"
#include "semantic/semantic_settings.h"
#include "system/run_settings.h"

namespace esdslam::cli {
namespace {

struct SegmentArgs {
  std::string settings;
  std::vector<std::string> images;
  std::string out_dir;
  std::string model;
  bool overlay = false;
};

// Frame timestamp for the folder segmenter: the image file name stem (<timestamp>.png).
double TimestampFromName(const std::filesystem::path& image) {
  try {
    return std::stod(image.stem().string());
  } catch (const std::exception&) {
    return 0.0;
  }
}

int RunSegment(const SegmentArgs& args) {
  SemanticSettings settings = LoadSemanticSettings(args.settings);
  if (!args.model.empty()) {
    SetModel(settings, args.model);
    settings.onnx.Check();
  }
  const auto segmenter = MakeSegmenter(settings);
  const ClassGroups groups(settings.groups);
  std::filesystem::create_directories(args.out_dir);
  for (const auto& image_path : args.images) {
    const cv::Mat bgr = cv::imread(image_path, cv::IMREAD_COLOR);
    if (bgr.empty()) throw InputError(image_path, 0, "cannot read image");
    const SegmentationResult result = segmenter->Segment(bgr, TimestampFromName(image_path));
    const std::string stem = std::filesystem::path(image_path).stem().string();
    const std::string labels_path = (std::filesystem::path(args.out_dir) / (stem + ".labels.png")).string();
    if (!cv::imwrite(labels_path, result.labels)) throw InputError(labels_path, 0, "cannot write labels");
    if (args.overlay) {
      const std::string overlay_path = (std::filesystem::path(args.out_dir) / (stem + ".overlay.png")).string();
      if (!cv::imwrite(overlay_path, DrawLabelOverlay(bgr, result.labels)))
        throw InputError(overlay_path, 0, "cannot write overlay");
    }
    const double dynamic_fraction = cv::countNonZero(groups.Masks(result.labels).dynamic) /
                                    static_cast<double>(result.labels.total());
    spdlog::info("{}: {:.1f} ms, dynamic pixels {:.1f}%", image_path, result.segment_ms, 100.0 * dynamic_fraction);
  }
  return 0;
}

const Registrar kRegistrar{Command{
    "segment", "Label images with the semantic segmenter (PASCAL VOC class ids)",
    [](CLI::App& app) -> RunFn {
      auto args = std::make_shared<SegmentArgs>();
      app.add_option("--settings", args->settings, "YAML settings (Semantic.* keys); default: built-in")
          ->check(CLI::ExistingFile);
      app.add_option("images", args->images, "Input images")->required()->check(CLI::ExistingFile);
      app.add_option("--out", args->out_dir, "Output folder for <stem>.labels.png (uint8 class ids)")->required();
      app.add_option("--model", args->model, "ONNX model, overrides Semantic.model");
      app.add_flag("--overlay", args->overlay, "Also write <stem>.overlay.png (colour overlay)");
      return [args] { return RunSegment(*args); };
    },
    40}};

}  // namespace
}  // namespace esdslam::cli
