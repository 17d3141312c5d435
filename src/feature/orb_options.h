#pragma once
// ORB extraction settings (ORB-SLAM2 keys ORBextractor.*).

#include "common/error.h"
#include "common/setting_error.h"

namespace esdslam {

struct OrbOptions {
  int num_features = 1000;     // ORBextractor.nFeatures: keypoints per frame (all levels)
  double scale_factor = 1.2;   // ORBextractor.scaleFactor: between pyramid levels
  int num_levels = 8;          // ORBextractor.nLevels
  int initial_fast_threshold = 20;  // ORBextractor.iniThFAST (intensity units)
  int min_fast_threshold = 7;       // ORBextractor.minThFAST: fallback in cells with no corner

  void Check() const {
    CheckRange("ORBextractor.nFeatures", num_features, 1, 100000);
    CheckRange("ORBextractor.scaleFactor", scale_factor, 1.001, 4.0);
    CheckRange("ORBextractor.nLevels", num_levels, 1, 32);
    CheckRange("ORBextractor.iniThFAST", initial_fast_threshold, 1, 255);
    CheckRange("ORBextractor.minThFAST", min_fast_threshold, 1, initial_fast_threshold);
  }
};

}  // namespace esdslam
