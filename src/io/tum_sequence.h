#pragma once
// RGB-D sequences in the TUM RGB-D benchmark layout (shared by the Bonn RGB-D Dynamic dataset):
//   DIR/rgb.txt, DIR/depth.txt   'timestamp relative/path.png' per line, '#' comments
//   DIR/groundtruth.txt          TUM trajectory (optional)
//   DIR/rgb/*.png                8-bit colour,  DIR/depth/*.png  16-bit, metres = value / factor
// rgb and depth are associated by nearest timestamp (see io/associate.h), or read from an
// ORB-SLAM2-style association file 'ts_rgb rgb/x.png ts_depth depth/y.png' (rgbd_tum's
// Examples/RGB-D/associations/*.txt): given explicitly, or detected when DIR has no rgb.txt and
// no depth.txt but one of DIR/associations.txt, association.txt, associate.txt.

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace esdslam {

struct AssociationOptions {
  double max_time_difference = 0.02;  // seconds, |t_rgb - t_depth| <= this
  std::string association_file;       // optional; relative paths inside it are relative to DIR
  void Check() const;                 // throws Error when max_time_difference is not > 0
};

struct FrameEntry {
  double timestamp = 0;  // rgb timestamp, seconds (the frame's time)
  std::string rgb_path;  // absolute, or DIR-joined
  double depth_timestamp = 0;
  std::string depth_path;
};

// The association file Open() reads for DIR when none is given (see above); empty = none.
std::string DetectAssociationFile(const std::string& dir);

class TumSequence {
 public:
  // Throws InputError when DIR is missing, a list file is missing or malformed (file and line),
  // timestamps are unsorted/duplicated, or no frame remains. Frames whose rgb or depth file is
  // missing on disk are skipped with a warning naming the file.
  static TumSequence Open(const std::string& dir, const AssociationOptions& options = {});

  const std::string& dir() const { return dir_; }
  const std::vector<FrameEntry>& frames() const { return frames_; }
  bool has_groundtruth() const;
  std::string groundtruth_path() const;  // DIR/groundtruth.txt (whether or not it exists)
  // Names of listed files that were skipped because they do not exist (for reports/tests).
  const std::vector<std::string>& skipped_files() const { return skipped_files_; }

 private:
  std::string dir_;
  std::vector<FrameEntry> frames_;
  std::vector<std::string> skipped_files_;
};

struct RgbdImages {
  cv::Mat bgr;      // CV_8UC3, OpenCV channel order as stored in the file's decoder output
  cv::Mat depth_m;  // CV_32F, metres, 0 = invalid
};

// Throws InputError naming the file when an image is missing, unreadable, of the wrong type
// (colour must be 8-bit 1/3/4 channels, depth 16-bit single channel) or the sizes differ.
RgbdImages LoadRgbd(const FrameEntry& frame, double depth_map_factor);

// The frame (sorted by timestamp) whose rgb timestamp is nearest to `timestamp` (seconds), or
// nullptr when none is within max_dt.
const FrameEntry* NearestFrame(const std::vector<FrameEntry>& frames, double timestamp, double max_dt);

}  // namespace esdslam
