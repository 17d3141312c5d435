#pragma once
// ORB extraction settings (ORB-SLAM2 keys ORBextractor.*).

#include "common/error.h"

namespace esdslam {

struct OrbOptions {
  int num_features = 1000;     // ORBextractor.nFeatures: keypoints per frame (all levels)
  double scale_factor = 1.2;   // ORBextractor.scaleFactor: between pyramid levels
  int num_levels = 8;          // ORBextractor.nLevels
  int initial_fast_threshold = 20;  // ORBextractor.iniThFAST (intensity units)
  int min_fast_threshold = 7;       // ORBextractor.minThFAST: fallback in cells with no corner

  void Check() const {
    if (num_features <= 0) throw Error("ORBextractor.nFeatures must be positive");
    if (!(scale_factor > 1.0)) throw Error("ORBextractor.scaleFactor must be > 1");
    if (num_levels <= 0 || num_levels > 32) throw Error("ORBextractor.nLevels must be in 1..32");
    if (initial_fast_threshold <= 0 || min_fast_threshold <= 0 || min_fast_threshold > initial_fast_threshold)
      throw Error("ORBextractor FAST thresholds must satisfy 0 < minThFAST <= iniThFAST");
  }
};

}  // namespace esdslam
