#include "synth/sequence_writer.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "common/error.h"
#include "io/trajectory_io.h"

namespace esdslam {
namespace {

namespace fs = std::filesystem;

std::string Stamp(double timestamp) { return fmt::format("{:.6f}", timestamp); }

void WritePng(const fs::path& path, const cv::Mat& image) {
  if (!cv::imwrite(path.string(), image)) throw Error(fmt::format("synth: cannot write {}", path.string()));
}

class ListFile {
 public:
  ListFile(const fs::path& path, const std::string& what) : path_(path), stream_(path) {
    if (!stream_) throw Error(fmt::format("synth: cannot write {}", path.string()));
    stream_ << "# " << what << "\n# synthetic sequence (esdslam synth)\n# timestamp filename\n";
  }
  void Add(double timestamp, const std::string& folder) {
    stream_ << Stamp(timestamp) << ' ' << folder << '/' << Stamp(timestamp) << ".png\n";
  }
  void Close() {
    stream_.close();
    if (!stream_) throw Error(fmt::format("synth: cannot write {}", path_.string()));
  }

 private:
  fs::path path_;
  std::ofstream stream_;
};

}  // namespace

cv::Mat DepthToPng16(const cv::Mat& depth_m, double factor) {
  cv::Mat out;
  depth_m.convertTo(out, CV_16U, factor);  // rounds to nearest, saturates
  return out;
}

cv::Mat Png16ToDepth(const cv::Mat& depth_png, double factor) {
  cv::Mat out;
  depth_png.convertTo(out, CV_32F, 1.0 / factor);
  return out;
}

cv::Mat MoverMaskToVocLabels(const cv::Mat& mover_mask) {
  cv::Mat labels = cv::Mat::zeros(mover_mask.size(), CV_8U);
  labels.setTo(kVocPersonClass, mover_mask > 0);
  return labels;
}

std::string SynthSettingsYaml(const SynthOptions& options) {
  const auto& k = options.intrinsics;
  std::string yaml = "%YAML:1.0\n# Synthetic RGB-D camera (esdslam synth): pinhole, no distortion.\n";
  yaml += fmt::format("Camera.fx: {:.6f}\nCamera.fy: {:.6f}\nCamera.cx: {:.6f}\nCamera.cy: {:.6f}\n", k.fx, k.fy, k.cx, k.cy);
  yaml += "Camera.k1: 0.0\nCamera.k2: 0.0\nCamera.p1: 0.0\nCamera.p2: 0.0\nCamera.k3: 0.0\n";
  yaml += fmt::format("Camera.width: {}\nCamera.height: {}\nCamera.fps: {:.1f}\n", k.width, k.height, options.fps);
  // The rolling shutter is part of the camera's calibration (absent: global shutter).
  if (options.readout_time_s > 0) yaml += fmt::format("Camera.readoutTime: {:.6g}\n", options.readout_time_s);
  yaml += "Camera.bf: 40.0\nCamera.RGB: 1\nThDepth: 40.0\n";
  yaml += fmt::format("DepthMapFactor: {:.1f}\n", kSynthDepthFactor);
  yaml += "ORBextractor.nFeatures: 1000\nORBextractor.scaleFactor: 1.2\nORBextractor.nLevels: 8\n";
  yaml += "ORBextractor.iniThFAST: 20\nORBextractor.minThFAST: 7\n";
  // Colour and depth are rendered with the same shutter (global, or rolling with the same row
  // times) at the same instant (up to the depth time offset): the depth image is misregistered
  // against the colour only by the motion during that offset (fraction of a frame), not by a
  // real sensor's separate timing.
  yaml += "# Misregistration of depth vs colour as a fraction of the motion per frame\n";
  yaml += fmt::format("Dynamic.check.motionWindowFraction: {:.3f}\n", std::abs(options.depth_time_offset) * options.fps);
  return yaml;
}

void WriteSynthSequence(const SyntheticScene& scene, const std::string& out_dir,
                        const std::function<void(int, int)>& progress) {
  const fs::path root(out_dir);
  std::error_code ec;
  for (const char* sub : {"rgb", "depth", "masks", "labels"}) {
    fs::create_directories(root / sub, ec);
    if (ec) throw Error(fmt::format("synth: cannot create {}: {}", (root / sub).string(), ec.message()));
  }
  ListFile rgb_list(root / "rgb.txt", "color images");
  ListFile depth_list(root / "depth.txt", "depth maps");
  ListFile mask_list(root / "masks.txt", "ground-truth mover masks (0 static, k = mover k)");
  ListFile label_list(root / "labels.txt", "PASCAL VOC labels (15 person)");
  for (int i = 0; i < scene.num_frames(); ++i) {
    const SynthFrame frame = scene.RenderFrame(i);
    const std::string rgb_stamp = Stamp(frame.timestamp);
    WritePng(root / "rgb" / (rgb_stamp + ".png"), frame.bgr);
    WritePng(root / "depth" / (Stamp(frame.depth_timestamp) + ".png"), DepthToPng16(frame.depth_m));
    WritePng(root / "masks" / (rgb_stamp + ".png"), frame.mover_mask);
    WritePng(root / "labels" / (rgb_stamp + ".png"), MoverMaskToVocLabels(frame.mover_mask));
    rgb_list.Add(frame.timestamp, "rgb");
    depth_list.Add(frame.depth_timestamp, "depth");
    mask_list.Add(frame.timestamp, "masks");
    label_list.Add(frame.timestamp, "labels");
    if (progress) progress(i + 1, scene.num_frames());
  }
  rgb_list.Close();
  depth_list.Close();
  mask_list.Close();
  label_list.Close();
  WriteTumTrajectory((root / "groundtruth.txt").string(), scene.GroundTruth());
  std::ofstream settings(root / "settings.yaml");
  settings << SynthSettingsYaml(scene.options());
  if (!settings) throw Error(fmt::format("synth: cannot write {}", (root / "settings.yaml").string()));
}

}  // namespace esdslam
