#pragma once
// Textured boxes, the only primitive of the synthetic scenes (room, furniture, movers), and
// ray-box intersection. Box frame: origin at the box centre, axes along the box edges.
// A box that is `inside_out` (the room) is seen from inside: rays hit its far side.

#include <array>
#include <limits>
#include <random>

#include <opencv2/core.hpp>

#include "common/geometry.h"
#include "synth/texture.h"

namespace esdslam {

struct TexturedBox {
  Vec3 half_size = Vec3::Ones();  // metres
  bool inside_out = false;
  int object_id = 0;              // 0 = static scene, k >= 1 = mover k
  double texel_m = 0.004;
  // Face f = 2 * axis + (positive side ? 1 : 0). Face textures are CV_8UC3 (BGR); texture
  // coordinates (metres from the face's corner): x faces (y, z), y faces (x, z), z faces (x, y).
  std::array<cv::Mat, 6> face_textures;
};

// Fills `box.face_textures` with independent textures of `style` (seeded by rng).
void TextureBox(TexturedBox& box, const TextureStyle& style, std::mt19937& rng);

// Intersects the ray origin + t * dir (box frame, dir need not be unit) with the box surface.
// Returns the smallest t > t_min on the visible side (entry for normal boxes, exit for inside-out
// ones) and the face index, or false.
bool IntersectBox(const TexturedBox& box, const Vec3& origin, const Vec3& dir, double t_min, double* t, int* face);

// Bilinear texture colour (BGR, 0..255) of the point `point_box` lying on `face`.
cv::Vec3f SampleBoxTexture(const TexturedBox& box, int face, const Vec3& point_box);

// Unit normal of `face` in the box frame, pointing towards the side the box is seen from.
Vec3 FaceNormal(const TexturedBox& box, int face);

}  // namespace esdslam
