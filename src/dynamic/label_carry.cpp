#include "dynamic/label_carry.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {
namespace {

constexpr std::uint8_t kYes = 255;

bool Valid(std::uint8_t state) { return state >= 128; }

// Nearest pixel index along an axis of `size` pixels (positions outside clamp to the border).
int NearestIndex(float v, int size) {
  return static_cast<int>(std::clamp(v, 0.f, static_cast<float>(size - 1)) + 0.5f);
}

// Label of flow pixel i: through its path into the source if the path is valid, else the filled one.
std::uint8_t LabelAt(int i, const cv::Vec2f* position, const cv::Vec2b* state, const std::uint8_t* filled,
                     const cv::Mat& source_labels) {
  if (!Valid(state[i][0])) return filled[i];
  return source_labels.at<std::uint8_t>(NearestIndex(position[i][1], source_labels.rows),
                                         NearestIndex(position[i][0], source_labels.cols));
}

// See label_carry.h: pixels that a surface moved in front of take the label of a labelled
// 4-neighbour on the same surface, breadth first from the labelled pixels. Also clears the filled
// label of pixels whose path is valid.
void FillFromSameSurface(const CarriedLabels& carried, const cv::Mat& nearer, const cv::Mat& depth_m,
                         const cv::Mat& source_labels, const DisocclusionOptions& options, cv::Mat& filled) {
  const int w = filled.cols, h = filled.rows;
  const cv::Vec2f* position = carried.source_position.ptr<cv::Vec2f>();
  const cv::Vec2b* state = carried.state.ptr<cv::Vec2b>();
  std::uint8_t* f = filled.ptr<std::uint8_t>();
  for (int i = 0; i < w * h; ++i) {
    if (Valid(state[i][0])) f[i] = kNoLabel;
  }
  if (depth_m.empty() || options.fill_abs_tolerance_m <= 0 || cv::countNonZero(nearer) == 0) return;
  const float* z = depth_m.ptr<float>();
  const std::uint8_t* in_front = nearer.ptr<std::uint8_t>();
  auto open = [&](int i) { return in_front[i] && !Valid(state[i][0]) && f[i] == kNoLabel && z[i] > 0; };
  // Seeds: labelled pixels with depth next to an open pixel, in pixel order.
  const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
  std::vector<int> queue;
  std::vector<std::uint8_t> queued_label;
  std::vector<std::uint8_t> seeded(static_cast<std::size_t>(w * h), 0);
  std::vector<int> candidates;
  for (int i = 0; i < w * h; ++i) {
    if (!open(i)) continue;
    const int x = i % w, y = i / w;
    for (int k = 0; k < 4; ++k) {
      const int nx = x + dx[k], ny = y + dy[k];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const int n = ny * w + nx;
      if (seeded[n] || !(z[n] > 0) || (!Valid(state[n][0]) && f[n] == kNoLabel)) continue;
      seeded[n] = 1;
      candidates.push_back(n);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  for (int n : candidates) {
    queue.push_back(n);
    queued_label.push_back(LabelAt(n, position, state, f, source_labels));
  }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int p = queue[head], px = p % w, py = p / w;
    const double tolerance = options.fill_abs_tolerance_m + options.fill_depth_sq_tolerance * z[p] * z[p];
    for (int k = 0; k < 4; ++k) {
      const int qx = px + dx[k], qy = py + dy[k];
      if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
      const int q = qy * w + qx;
      if (!open(q) || std::abs(z[q] - z[p]) > tolerance) continue;
      f[q] = queued_label[head];
      queue.push_back(q);
      queued_label.push_back(f[q]);
    }
  }
}

}  // namespace

void DisocclusionOptions::Check() const {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw Error(fmt::format("DisocclusionOptions: {}", what));
  };
  require(occlusion_abs_tolerance_m <= 10, "occlusion_abs_tolerance_m must be <= 10 m (<= 0 disables the test)");
  require(occlusion_depth_sq_tolerance >= 0 && occlusion_depth_sq_tolerance <= 1,
          "occlusion_depth_sq_tolerance must be in [0, 1] 1/m");
  require(fill_abs_tolerance_m <= 10, "fill_abs_tolerance_m must be <= 10 m (<= 0 disables the fill)");
  require(fill_depth_sq_tolerance >= 0 && fill_depth_sq_tolerance <= 1, "fill_depth_sq_tolerance must be in [0, 1] 1/m");
  require(depth_memory_frames >= 0 && depth_memory_frames <= 100, "depth_memory_frames must be in [0, 100]");
}

RememberedDepth RememberDepth(const cv::Mat& depth_m) {
  if (depth_m.empty()) return {};
  return {depth_m, cv::Mat::zeros(depth_m.size(), CV_8U)};
}

FlowStep MakeFlowStep(const cv::Mat& backward_flow, const cv::Mat& depth_m, const RememberedDepth& prev,
                      const DisocclusionOptions& options, RememberedDepth* remembered) {
  CV_Assert(backward_flow.type() == CV_32FC2);
  const int w = backward_flow.cols, h = backward_flow.rows;
  const bool test = options.occlusion_abs_tolerance_m > 0 && !depth_m.empty() && !prev.depth_m.empty();
  CV_Assert(depth_m.empty() || depth_m.size() == backward_flow.size());
  CV_Assert(prev.depth_m.empty() || prev.depth_m.size() == backward_flow.size());
  FlowStep step{cv::Mat(backward_flow.size(), CV_32FC2), cv::Mat(backward_flow.size(), CV_8UC2),
                cv::Mat::zeros(backward_flow.size(), CV_8U)};
  *remembered = RememberDepth(depth_m);
  const bool remember = !depth_m.empty() && !prev.depth_m.empty() && options.depth_memory_frames > 0;
  if (remember) remembered->depth_m = depth_m.clone();
  for (int y = 0; y < h; ++y) {
    const cv::Vec2f* flow = backward_flow.ptr<cv::Vec2f>(y);
    const float* z = depth_m.empty() ? nullptr : depth_m.ptr<float>(y);
    cv::Vec2f* position = step.position_in_prev.ptr<cv::Vec2f>(y);
    cv::Vec2b* keep = step.keep.ptr<cv::Vec2b>(y);
    std::uint8_t* nearer = step.nearer.ptr<std::uint8_t>(y);
    for (int x = 0; x < w; ++x) {
      const cv::Vec2f p(static_cast<float>(x) + flow[x][0], static_cast<float>(y) + flow[x][1]);
      position[x] = p;
      const bool inside = p[0] >= 0 && p[1] >= 0 && p[0] <= static_cast<float>(w - 1) && p[1] <= static_cast<float>(h - 1);
      bool consistent = true;
      if (test || remember) {
        const int u = NearestIndex(p[0], w), v = NearestIndex(p[1], h);
        const float z_prev = prev.depth_m.at<float>(v, u);
        if (test && z[x] > 0 && z_prev > 0) {
          const double tolerance = options.occlusion_abs_tolerance_m + options.occlusion_depth_sq_tolerance * z[x] * z[x];
          consistent = std::abs(z[x] - z_prev) <= tolerance;
          if (!consistent && z[x] < z_prev) nearer[x] = kYes;
        }
        const std::uint8_t age_prev = prev.age.at<std::uint8_t>(v, u);
        if (remember && !(z[x] > 0) && z_prev > 0 && age_prev < options.depth_memory_frames) {
          remembered->depth_m.at<float>(y, x) = z_prev;
          remembered->age.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(age_prev + 1);
        }
      }
      keep[x] = cv::Vec2b(consistent ? kYes : 0, consistent && inside ? kYes : 0);
    }
  }
  return step;
}

CarriedLabels StartCarry(cv::Size flow_size, cv::Size image_size) {
  CarriedLabels carried{cv::Mat(flow_size, CV_32FC2), cv::Mat(flow_size, CV_8UC2, cv::Scalar(kYes, kYes)),
                        cv::Mat(flow_size, CV_8U, cv::Scalar(kNoLabel))};
  // Flow pixel centre (x + 0.5) / flow width = image pixel centre (u + 0.5) / image width.
  const float sx = static_cast<float>(image_size.width) / static_cast<float>(flow_size.width);
  const float sy = static_cast<float>(image_size.height) / static_cast<float>(flow_size.height);
  for (int y = 0; y < flow_size.height; ++y) {
    cv::Vec2f* row = carried.source_position.ptr<cv::Vec2f>(y);
    for (int x = 0; x < flow_size.width; ++x)
      row[x] = cv::Vec2f((static_cast<float>(x) + 0.5f) * sx - 0.5f, (static_cast<float>(y) + 0.5f) * sy - 0.5f);
  }
  return carried;
}

void CarryOneStep(const FlowStep& step, const cv::Mat& depth_m, const cv::Mat& source_labels,
                  const DisocclusionOptions& options, CarriedLabels& carried) {
  const int w = carried.state.cols, h = carried.state.rows;
  CarriedLabels next{cv::Mat(carried.state.size(), CV_32FC2), cv::Mat(carried.state.size(), CV_8UC2),
                     cv::Mat(carried.state.size(), CV_8U)};
  // One pass, as cv::remap with BORDER_REPLICATE: bilinear for the positions, nearest for the state
  // flags and filled labels; then the step's keep flags.
  const cv::Vec2f* position = carried.source_position.ptr<cv::Vec2f>();
  const cv::Vec2b* state = carried.state.ptr<cv::Vec2b>();
  const std::uint8_t* filled = carried.filled.ptr<std::uint8_t>();
  for (int y = 0; y < h; ++y) {
    const cv::Vec2f* p = step.position_in_prev.ptr<cv::Vec2f>(y);
    const cv::Vec2b* keep = step.keep.ptr<cv::Vec2b>(y);
    cv::Vec2f* out_position = next.source_position.ptr<cv::Vec2f>(y);
    cv::Vec2b* out_state = next.state.ptr<cv::Vec2b>(y);
    std::uint8_t* out_filled = next.filled.ptr<std::uint8_t>(y);
    for (int x = 0; x < w; ++x) {
      const float u = std::clamp(p[x][0], 0.f, static_cast<float>(w - 1));
      const float v = std::clamp(p[x][1], 0.f, static_cast<float>(h - 1));
      const int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
      const int u1 = std::min(u0 + 1, w - 1), v1 = std::min(v0 + 1, h - 1);
      const float a = u - static_cast<float>(u0), b = v - static_cast<float>(v0);
      const float w00 = (1 - a) * (1 - b), w10 = a * (1 - b), w01 = (1 - a) * b, w11 = a * b;
      const cv::Vec2f &p00 = position[v0 * w + u0], &p10 = position[v0 * w + u1];
      const cv::Vec2f &p01 = position[v1 * w + u0], &p11 = position[v1 * w + u1];
      out_position[x][0] = w00 * p00[0] + w10 * p10[0] + w01 * p01[0] + w11 * p11[0];
      out_position[x][1] = w00 * p00[1] + w10 * p10[1] + w01 * p01[1] + w11 * p11[1];
      const int nearest = (b < 0.5f ? v0 : v1) * w + (a < 0.5f ? u0 : u1);
      out_state[x][0] = state[nearest][0] & keep[x][0];
      out_state[x][1] = state[nearest][1] & keep[x][1];
      out_filled[x] = filled[nearest];
    }
  }
  FillFromSameSurface(next, step.nearer, depth_m, source_labels, options, next.filled);
  carried = std::move(next);
}

CarriedImages CarriedLabelImages(const CarriedLabels& carried, const cv::Mat& source_labels,
                                 const cv::Mat& source_dynamic, const std::array<std::uint8_t, 256>& dynamic_of_label) {
  CV_Assert(source_labels.type() == CV_8U && source_dynamic.type() == CV_8U && source_labels.size() == source_dynamic.size());
  const int w = carried.state.cols, h = carried.state.rows;
  const int cols = source_labels.cols, rows = source_labels.rows;
  CarriedImages out{cv::Mat(carried.state.size(), CV_8U), cv::Mat(carried.state.size(), CV_8U), 0.0};
  int uncovered = 0;
  for (int y = 0; y < h; ++y) {
    const cv::Vec2f* position = carried.source_position.ptr<cv::Vec2f>(y);
    const cv::Vec2b* state = carried.state.ptr<cv::Vec2b>(y);
    const std::uint8_t* filled = carried.filled.ptr<std::uint8_t>(y);
    std::uint8_t* labels = out.labels.ptr<std::uint8_t>(y);
    std::uint8_t* dynamic = out.dynamic.ptr<std::uint8_t>(y);
    for (int x = 0; x < w; ++x) {
      uncovered += Valid(state[x][1]) ? 0 : 1;
      if (!Valid(state[x][0])) {
        labels[x] = filled[x] == kNoLabel ? 0 : filled[x];
        dynamic[x] = dynamic_of_label[labels[x]];
        continue;
      }
      const float u = std::clamp(position[x][0], 0.f, static_cast<float>(cols - 1));
      const float v = std::clamp(position[x][1], 0.f, static_cast<float>(rows - 1));
      const int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
      const int u1 = std::min(u0 + 1, cols - 1), v1 = std::min(v0 + 1, rows - 1);
      const float a = u - static_cast<float>(u0), b = v - static_cast<float>(v0);
      labels[x] = source_labels.at<std::uint8_t>(b < 0.5f ? v0 : v1, a < 0.5f ? u0 : u1);
      const std::uint8_t* d0 = source_dynamic.ptr<std::uint8_t>(v0);
      const std::uint8_t* d1 = source_dynamic.ptr<std::uint8_t>(v1);
      const float d = (1 - b) * ((1 - a) * d0[u0] + a * d0[u1]) + b * ((1 - a) * d1[u0] + a * d1[u1]);
      dynamic[x] = static_cast<std::uint8_t>(d + 0.5f);
    }
  }
  out.uncovered_fraction = static_cast<double>(uncovered) / static_cast<double>(out.labels.total());
  return out;
}

}  // namespace esdslam
