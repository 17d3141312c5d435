#include "synth/textured_box.h"

#include <algorithm>
#include <cmath>

namespace esdslam {
namespace {

// The two box axes spanning face `axis` (texture columns, texture rows).
void FaceAxes(int axis, int* col_axis, int* row_axis) {
  *col_axis = axis == 0 ? 1 : 0;
  *row_axis = axis == 2 ? 1 : 2;
}

}  // namespace

void TextureBox(TexturedBox& box, const TextureStyle& style, std::mt19937& rng) {
  for (int face = 0; face < 6; ++face) {
    int col_axis, row_axis;
    FaceAxes(face / 2, &col_axis, &row_axis);
    box.face_textures[face] =
        MakeTexture(2 * box.half_size[col_axis], 2 * box.half_size[row_axis], box.texel_m, style, rng);
  }
}

bool IntersectBox(const TexturedBox& box, const Vec3& origin, const Vec3& dir, double t_min, double* t, int* face) {
  double t_near = -std::numeric_limits<double>::infinity();
  double t_far = std::numeric_limits<double>::infinity();
  int near_face = -1, far_face = -1;
  for (int axis = 0; axis < 3; ++axis) {
    const double h = box.half_size[axis];
    if (dir[axis] == 0.0) {
      if (origin[axis] < -h || origin[axis] > h) return false;
      continue;
    }
    const double inv = 1.0 / dir[axis];
    double t_low = (-h - origin[axis]) * inv;   // plane of the negative face
    double t_high = (h - origin[axis]) * inv;   // plane of the positive face
    int low_face = 2 * axis, high_face = 2 * axis + 1;
    if (t_low > t_high) {
      std::swap(t_low, t_high);
      std::swap(low_face, high_face);
    }
    if (t_low > t_near) {
      t_near = t_low;
      near_face = low_face;
    }
    if (t_high < t_far) {
      t_far = t_high;
      far_face = high_face;
    }
  }
  if (t_near > t_far) return false;
  if (box.inside_out) {
    if (!(t_far > t_min) || far_face < 0) return false;
    *t = t_far;
    *face = far_face;
    return true;
  }
  if (!(t_near > t_min) || near_face < 0) return false;
  *t = t_near;
  *face = near_face;
  return true;
}

cv::Vec3f SampleBoxTexture(const TexturedBox& box, int face, const Vec3& point_box) {
  int col_axis, row_axis;
  FaceAxes(face / 2, &col_axis, &row_axis);
  const cv::Mat& texture = box.face_textures[face];
  // Texel (i, j) covers [i, i + 1) * texel_m; its value sits at its centre.
  const double x = (point_box[col_axis] + box.half_size[col_axis]) / box.texel_m - 0.5;
  const double y = (point_box[row_axis] + box.half_size[row_axis]) / box.texel_m - 0.5;
  const double xc = std::clamp(x, 0.0, texture.cols - 1.001);
  const double yc = std::clamp(y, 0.0, texture.rows - 1.001);
  const int x0 = static_cast<int>(xc), y0 = static_cast<int>(yc);
  const float fx = static_cast<float>(xc - x0), fy = static_cast<float>(yc - y0);
  const cv::Vec3b* row0 = texture.ptr<cv::Vec3b>(y0);
  const cv::Vec3b* row1 = texture.ptr<cv::Vec3b>(y0 + 1);
  cv::Vec3f out;
  for (int c = 0; c < 3; ++c) {
    const float top = row0[x0][c] + fx * (row0[x0 + 1][c] - row0[x0][c]);
    const float bottom = row1[x0][c] + fx * (row1[x0 + 1][c] - row1[x0][c]);
    out[c] = top + fy * (bottom - top);
  }
  return out;
}

Vec3 FaceNormal(const TexturedBox& box, int face) {
  Vec3 n = Vec3::Zero();
  n[face / 2] = (face % 2 == 1) ? 1.0 : -1.0;  // outward
  return box.inside_out ? Vec3(-n) : n;
}

}  // namespace esdslam
