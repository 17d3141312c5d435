#pragma once
// Reads precomputed label images instead of running a network, for users who segment offline
// with a larger model. The folder holds one PNG per frame named <timestamp>.png (the frame's
// timestamp in seconds as written in rgb.txt, e.g. 1548339828.254410.png), each a single-channel
// 8-bit image of class ids. A frame gets the mask whose timestamp is nearest to its own, if
// |difference| <= tolerance_s. A mask of a different size than the frame is resized with
// nearest neighbour.
//
// Missing mask (no file within the tolerance): by default an Error naming the folder and the
// timestamp. With allow_missing = true the frame gets all-background labels (class 0) and a
// warning is logged, i.e. nothing in it is treated as dynamic.

#include <string>
#include <vector>

#include "semantic/segmenter.h"

namespace esdslam {

struct FolderSegmenterOptions {
  std::string folder;          // Semantic.maskFolder
  double tolerance_s = 0.02;   // Semantic.maskTolerance (seconds)
  bool allow_missing = false;  // Semantic.allowMissingMasks

  void Check() const;
};

class FolderSegmenter : public Segmenter {
 public:
  // Indexes the folder; throws Error if it does not exist or holds no <timestamp>.png file.
  explicit FolderSegmenter(FolderSegmenterOptions options);

  SegmentationResult Segment(const cv::Mat& bgr, double timestamp) override;
  std::string Name() const override { return "folder:" + options_.folder; }

  std::size_t NumMasks() const { return masks_.size(); }

 private:
  struct MaskFile {
    double timestamp;
    std::string path;
  };
  // The mask file nearest to `timestamp` within the tolerance, or nullptr.
  const MaskFile* Find(double timestamp) const;

  FolderSegmenterOptions options_;
  std::vector<MaskFile> masks_;  // sorted by timestamp
};

}  // namespace esdslam
