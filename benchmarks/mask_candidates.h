#pragma once
// The mask-prediction candidates compared by mask_prediction_bench.cpp. Each one is started on
// the labels of a source frame s and advanced frame by frame; Predict() gives its dynamic mask
// (CV_8U, 255) for the newest frame. Only the first argument of FrameData that a candidate needs
// is used; all share the evaluation in the benchmark.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "camera/pinhole_camera.h"
#include "common/geometry.h"
#include "dynamic/mask_predictor.h"
#include "dynamic/semantic_front_end.h"

namespace esdslam::bench {

struct FrameData {
  cv::Mat grey;          // CV_8U, full resolution
  cv::Mat depth_m;       // CV_32F metres
  cv::Mat labels;        // CV_8U class ids: the labels the network gives (or perfect synthetic ones)
  cv::Mat truth;         // CV_8U 255 = dynamic in the ground truth (synthetic) or in the fresh labels (real)
  cv::Mat truth_refined; // synthetic: truth; real: the fresh labels' person mask refined as a prediction is
  Rigid3 world_from_cam; // ground truth pose
};

class Candidate {
 public:
  virtual ~Candidate() = default;
  virtual std::string Name() const = 0;
  virtual void Start(const FrameData& source) = 0;
  virtual void Advance(const FrameData& frame) = 0;
  virtual cv::Mat Predict() = 0;
};

inline cv::Mat PersonMask(const cv::Mat& labels) { return labels == 15; }

// The source mask unchanged.
class HoldCandidate : public Candidate {
 public:
  std::string Name() const override { return "hold"; }
  void Start(const FrameData& source) override { mask_ = PersonMask(source.labels); }
  void Advance(const FrameData&) override {}
  cv::Mat Predict() override { return mask_; }

 private:
  cv::Mat mask_;
};

// The camera's motion only (today's --realtime warp): the source mask forward-warped with the
// source depth and the relative pose (here the ground truth: the best a motion model can give).
class CameraCandidate : public Candidate {
 public:
  explicit CameraCandidate(const PinholeCamera& camera) : camera_(camera) {}
  std::string Name() const override { return "camera"; }
  void Start(const FrameData& source) override {
    mask_ = PersonMask(source.labels);
    depth_ = source.depth_m;
    world_from_source_ = world_from_current_ = source.world_from_cam;
  }
  void Advance(const FrameData& frame) override { world_from_current_ = frame.world_from_cam; }
  cv::Mat Predict() override {
    return WarpMask(mask_, depth_, world_from_current_.inverse() * world_from_source_, camera_, 0);
  }

 private:
  PinholeCamera camera_;
  cv::Mat mask_, depth_;
  Rigid3 world_from_source_, world_from_current_;
};

// Corners on the person (source mask eroded) tracked frame to frame with pyramidal Lucas-Kanade;
// each connected component of the source mask moves by the similarity its points fit (RANSAC),
// or stays where it is with fewer than 3 points.
class KeypointCandidate : public Candidate {
 public:
  std::string Name() const override { return "keypoints"; }
  void Start(const FrameData& source) override {
    mask_ = PersonMask(source.labels);
    num_components_ = cv::connectedComponents(mask_, components_, 8, CV_32S);
    cv::Mat inner;
    cv::erode(mask_, inner, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(9, 9)));
    start_.clear();
    if (cv::countNonZero(inner) > 0) cv::goodFeaturesToTrack(source.grey, start_, 300, 0.01, 6, inner);
    now_ = start_;
    alive_.assign(start_.size(), 1);
    previous_ = source.grey;
  }
  void Advance(const FrameData& frame) override {
    if (!now_.empty()) {
      std::vector<cv::Point2f> next;
      std::vector<uchar> status;
      std::vector<float> error;
      cv::calcOpticalFlowPyrLK(previous_, frame.grey, now_, next, status, error, cv::Size(21, 21), 3);
      for (std::size_t i = 0; i < next.size(); ++i) alive_[i] = alive_[i] && status[i];
      now_ = next;
    }
    previous_ = frame.grey;
  }
  cv::Mat Predict() override {
    cv::Mat out = cv::Mat::zeros(mask_.size(), CV_8U);
    for (int c = 1; c < num_components_; ++c) {
      std::vector<cv::Point2f> from, to;
      for (std::size_t i = 0; i < start_.size(); ++i) {
        if (!alive_[i] || components_.at<int>(cvRound(start_[i].y), cvRound(start_[i].x)) != c) continue;
        from.push_back(start_[i]);
        to.push_back(now_[i]);
      }
      const cv::Mat component = components_ == c;
      cv::Mat motion;
      if (from.size() >= 3) motion = cv::estimateAffinePartial2D(from, to, cv::noArray(), cv::RANSAC, 3.0);
      if (motion.empty()) {
        out.setTo(255, component);
        continue;
      }
      cv::Mat moved;
      cv::warpAffine(component, moved, motion, mask_.size(), cv::INTER_NEAREST);
      out.setTo(255, moved);
    }
    return out;
  }

 private:
  cv::Mat mask_, components_, previous_;
  int num_components_ = 0;
  std::vector<cv::Point2f> start_, now_;
  std::vector<uchar> alive_;
};

// The component (dynamic/mask_predictor.h): labels carried along chained DIS flows.
class FlowCandidate : public Candidate {
 public:
  FlowCandidate(std::string name, cv::Size size, MaskPredictorOptions options)
      : name_(std::move(name)), size_(size), options_(options) {}
  std::string Name() const override { return name_; }
  void Start(const FrameData& source) override {
    predictor_ = std::make_unique<MaskPredictor>(size_, options_);
    predictor_->AddFrame(++id_, source.grey, source.depth_m);
    predictor_->AddLabels(id_, source.labels);
  }
  void Advance(const FrameData& frame) override { predictor_->AddFrame(++id_, frame.grey, frame.depth_m); }
  cv::Mat Predict() override {
    last_ = predictor_->Predict();
    return last_.masks.dynamic;
  }
  const MaskPrediction& last() const { return last_; }

 private:
  std::string name_;
  cv::Size size_;
  MaskPredictorOptions options_;
  std::unique_ptr<MaskPredictor> predictor_;
  std::int64_t id_ = 0;
  MaskPrediction last_;
};

}  // namespace esdslam::bench
