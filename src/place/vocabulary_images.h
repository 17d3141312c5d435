#pragma once
// Training inputs for the vocabulary: image files from folders and their ORB descriptors.

#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "feature/orb_options.h"

namespace esdslam {

// Image files (.png, .jpg, .jpeg, .ppm, .pgm) directly in each folder, or in its rgb/ subfolder
// when the folder has one (TUM layout); sorted by name within a folder, folders in the given
// order. max_images > 0 keeps that many, evenly spaced over the whole list. Throws Error when a
// folder does not exist.
std::vector<std::string> ListTrainingImages(const std::vector<std::string>& folders, int max_images = 0);

// ORB descriptors (N x 32 CV_8U) of each image, read as grey scale. `progress(done, total)` is
// called after each image. Throws InputError on an unreadable image.
std::vector<cv::Mat> ExtractTrainingDescriptors(const std::vector<std::string>& image_paths, const OrbOptions& options,
                                                const std::function<void(int, int)>& progress = {});

}  // namespace esdslam
