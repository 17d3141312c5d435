#include "place/vocabulary_images.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "common/error.h"
#include "feature/orb_extractor.h"

namespace esdslam {
namespace fs = std::filesystem;

namespace {
bool IsImageFile(const fs::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".png" || extension == ".jpg" || extension == ".jpeg" || extension == ".ppm" ||
         extension == ".pgm";
}
}  // namespace

std::vector<std::string> ListTrainingImages(const std::vector<std::string>& folders, int max_images) {
  std::vector<std::string> all;
  for (const std::string& folder : folders) {
    fs::path dir(folder);
    if (!fs::is_directory(dir)) throw Error(fmt::format("image folder {} does not exist", folder));
    if (fs::is_directory(dir / "rgb")) dir /= "rgb";
    std::vector<std::string> files;
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (entry.is_regular_file() && IsImageFile(entry.path())) files.push_back(entry.path().string());
    }
    std::sort(files.begin(), files.end());
    all.insert(all.end(), files.begin(), files.end());
  }
  if (max_images <= 0 || static_cast<int>(all.size()) <= max_images) return all;
  std::vector<std::string> kept;
  for (int i = 0; i < max_images; ++i) {
    kept.push_back(all[static_cast<std::size_t>(static_cast<double>(i) * all.size() / max_images)]);
  }
  return kept;
}

std::vector<cv::Mat> ExtractTrainingDescriptors(const std::vector<std::string>& image_paths, const OrbOptions& options,
                                                const std::function<void(int, int)>& progress) {
  const OrbExtractor extractor(options);
  std::vector<cv::Mat> descriptors;
  descriptors.reserve(image_paths.size());
  for (std::size_t i = 0; i < image_paths.size(); ++i) {
    const cv::Mat gray = cv::imread(image_paths[i], cv::IMREAD_GRAYSCALE);
    if (gray.empty()) throw InputError(image_paths[i], 0, "cannot read image");
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat image_descriptors;
    extractor.Extract(gray, cv::Mat(), &keypoints, &image_descriptors);
    descriptors.push_back(image_descriptors);
    if (progress) progress(static_cast<int>(i + 1), static_cast<int>(image_paths.size()));
  }
  return descriptors;
}

}  // namespace esdslam
