#pragma once
// Writes a synthetic scene as a sequence in TUM RGB-D layout:
//   rgb/<t>.png  depth/<t>.png (16-bit, metres * 5000, 0 = invalid)  rgb.txt  depth.txt
//   groundtruth.txt (world_from_cam, TUM format)
//   masks/<t>.png (uint8: 0 static, k = mover k) + masks.txt
//   labels/<t>.png (uint8 PASCAL VOC class ids: 15 person on movers, 0 elsewhere) + labels.txt
//   settings.yaml (ORB-SLAM2 keys for the synthetic camera, plus Camera.readoutTime when it has a
//   rolling shutter)
// <t> is the frame's timestamp with 6 decimals; masks and labels use the rgb timestamp.

#include <functional>
#include <string>

#include <opencv2/core.hpp>

#include "synth/synthetic_scene.h"

namespace esdslam {

constexpr double kSynthDepthFactor = 5000.0;  // PNG value per metre
constexpr int kVocPersonClass = 15;

// CV_32F metres -> CV_16U at `factor` per metre (rounded; 0 stays 0 = invalid).
cv::Mat DepthToPng16(const cv::Mat& depth_m, double factor = kSynthDepthFactor);
// CV_16U -> CV_32F metres.
cv::Mat Png16ToDepth(const cv::Mat& depth_png, double factor = kSynthDepthFactor);
// Mover mask (ids) -> VOC label image (15 where a mover is, 0 elsewhere).
cv::Mat MoverMaskToVocLabels(const cv::Mat& mover_mask);

// The ORB-SLAM2 settings file for the scene's camera (starts with %YAML:1.0).
std::string SynthSettingsYaml(const SynthOptions& options);

// Renders and writes every frame of `scene` into `out_dir` (created if missing). `progress`
// (optional) is called after each frame with (frames done, total). Throws Error when a file
// cannot be written.
void WriteSynthSequence(const SyntheticScene& scene, const std::string& out_dir,
                        const std::function<void(int, int)>& progress = {});

}  // namespace esdslam
