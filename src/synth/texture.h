#pragma once
// Procedural surface textures for the synthetic scenes: a "dead leaves" image (random opaque
// rectangles, ellipses and triangles drawn from large to small) with posters of fine detail.
// Occlusions between shapes of many sizes make corners at every scale, and random placement,
// colours and grey levels make every neighbourhood distinctive (no repeated pattern), which is
// what ORB/FAST matching needs. Textures are defined per surface in metres, so they are fixed
// in the world and the rendered views are consistent.

#include <random>
#include <vector>

#include <opencv2/core.hpp>

namespace esdslam {

struct TextureStyle {
  cv::Vec3b base_bgr{128, 128, 128};
  // Shape sizes in metres (largest first) and the fraction of the surface each layer covers.
  std::vector<double> scales_m{0.8, 0.4, 0.2, 0.1, 0.05, 0.03};
  std::vector<double> coverage{0.6, 0.5, 0.4, 0.25, 0.15, 0.08};
  double colour_probability = 0.5;  // otherwise a grey level
  double posters_per_m2 = 0.12;     // fine-detail rectangles (0.25-0.6 m)
};

// A width_m x height_m surface at texel_m metres per texel: CV_8UC3 (BGR), cols along width.
cv::Mat MakeTexture(double width_m, double height_m, double texel_m, const TextureStyle& style, std::mt19937& rng);

}  // namespace esdslam
