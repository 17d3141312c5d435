// The mask stage made ahead on its own thread gives the same masks, in the same order, as the
// inline stage; a failure of the front end reaches the caller; Stop leaves unasked frames.
#include "dynamic/mask_ahead.h"

#include <condition_variable>
#include <mutex>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {
namespace {

constexpr int kWidth = 160, kHeight = 120;
constexpr int kPersonClass = 15;  // VOC's person

// A person square that moves 4 px right per frame (its position is read from the image, where
// the test draws it), and a failure on one timestamp.
class SquareSegmenter : public Segmenter {
 public:
  explicit SquareSegmenter(double fail_at = -1) : fail_at_(fail_at) {}
  SegmentationResult Segment(const cv::Mat& bgr, double timestamp) override {
    if (timestamp == fail_at_) throw Error("fake failure");
    SegmentationResult r;
    cv::Mat gray;
    cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
    r.labels = cv::Mat::zeros(bgr.size(), CV_8U);
    r.labels.setTo(kPersonClass, gray > 128);
    return r;
  }
  std::string Name() const override { return "square"; }

 private:
  double fail_at_;
};

struct TestFrame {
  double timestamp;
  cv::Mat bgr, depth_m;
};

TestFrame MakeFrame(int id) {
  TestFrame f{100.0 + id, cv::Mat(kHeight, kWidth, CV_8UC3, cv::Scalar::all(40)),
              cv::Mat(kHeight, kWidth, CV_32F, cv::Scalar(3.0f))};
  const cv::Rect square(20 + 4 * id, 30, 30, 50);
  f.bgr(square).setTo(cv::Scalar::all(220));
  f.depth_m(square).setTo(1.5f);  // the person stands in front of a wall
  return f;
}

SemanticSettings Settings(int segment_every) {
  SemanticSettings settings;
  settings.segment_every = segment_every;
  settings.label_delay_frames = 1;
  return settings;
}

std::unique_ptr<MaskAhead> MakeStage(int segment_every, WorkerMode mode, double fail_at = -1) {
  // wait_for_due_labels: the masks do not depend on the network's timing, so both modes compare.
  auto front_end = std::make_unique<SemanticFrontEnd>(std::make_unique<SquareSegmenter>(fail_at),
                                                      Settings(segment_every), RegionGrowingOptions{}, MaskRefineOptions{}, true);
  return std::make_unique<MaskAhead>(std::move(front_end), mode);
}

// Runs the pipeline's order: submit frame i+1, then take frame i's mask.
std::vector<DynamicMaskResult> RunFrames(MaskAhead& stage, int count) {
  std::vector<TestFrame> frames;
  for (int i = 0; i < count; ++i) frames.push_back(MakeFrame(i));
  std::vector<DynamicMaskResult> masks;
  stage.Submit(0, frames[0].timestamp, frames[0].bgr, frames[0].depth_m);
  for (int i = 0; i < count; ++i) {
    if (i + 1 < count) stage.Submit(i + 1, frames[i + 1].timestamp, frames[i + 1].bgr, frames[i + 1].depth_m);
    MaskAheadResult made = stage.MaskFor(i, frames[i].bgr, frames[i].depth_m);
    EXPECT_GE(made.wait_ms, 0);
    masks.push_back(std::move(made.mask));
  }
  stage.Stop();
  return masks;
}

class MaskAheadModes : public testing::TestWithParam<int> {};

TEST_P(MaskAheadModes, ThreadedMasksEqualInlineMasks) {
  auto threaded = MakeStage(GetParam(), WorkerMode::kThread);
  auto in_line = MakeStage(GetParam(), WorkerMode::kInline);
  const std::vector<DynamicMaskResult> a = RunFrames(*threaded, 10);
  const std::vector<DynamicMaskResult> b = RunFrames(*in_line, 10);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].source_id, b[i].source_id) << "frame " << i;
    ASSERT_FALSE(a[i].mask.empty()) << "frame " << i;
    EXPECT_EQ(cv::countNonZero(a[i].mask != b[i].mask), 0) << "frame " << i;
    // The square is on the mask (the carried labels follow it).
    EXPECT_GT(a[i].mask.at<std::uint8_t>(55, 35 + 4 * static_cast<int>(i)), 0) << "frame " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(EveryFrameAndPredicted, MaskAheadModes, testing::Values(1, 3));

TEST(MaskAhead, FrontEndFailureReachesTheCaller) {
  auto stage = MakeStage(1, WorkerMode::kThread, /*fail_at=*/102.0);
  std::vector<TestFrame> frames;
  for (int i = 0; i < 3; ++i) frames.push_back(MakeFrame(i));
  // Up to the failing frame: a Submit after the failure throws (the failure may come at once).
  for (int i = 0; i < 3; ++i) stage->Submit(i, frames[i].timestamp, frames[i].bgr, frames[i].depth_m);
  EXPECT_NO_THROW(stage->MaskFor(0, frames[0].bgr, frames[0].depth_m));
  EXPECT_NO_THROW(stage->MaskFor(1, frames[1].bgr, frames[1].depth_m));
  try {
    stage->MaskFor(2, frames[2].bgr, frames[2].depth_m);
    FAIL() << "expected the failure of frame 2";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mask stage failed"), std::string::npos) << e.what();
  }
  EXPECT_THROW(stage->Submit(3, 103.0, frames[0].bgr, frames[0].depth_m), Error);
}

TEST(MaskAhead, StopWithFramesNotAskedForReturns) {
  auto stage = MakeStage(3, WorkerMode::kThread);
  for (int i = 0; i < 2; ++i) {
    const TestFrame f = MakeFrame(i);
    stage->Submit(i, f.timestamp, f.bgr, f.depth_m);
  }
  stage->Stop();
  stage->Stop();  // twice is harmless
  const TestFrame f = MakeFrame(2);
  EXPECT_THROW(stage->Submit(2, f.timestamp, f.bgr, f.depth_m), Error);
}

// The square segmenter, held at its first frame until Open(): the network's first labels late.
class GatedSegmenter : public Segmenter {
 public:
  SegmentationResult Segment(const cv::Mat& bgr, double timestamp) override {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      opened_.wait(lock, [&] { return open_; });
    }
    return square_.Segment(bgr, timestamp);
  }
  std::string Name() const override { return "gated square"; }
  void Open() {
    std::lock_guard<std::mutex> lock(mutex_);
    open_ = true;
    opened_.notify_all();
  }

 private:
  SquareSegmenter square_;
  std::mutex mutex_;
  std::condition_variable opened_;
  bool open_ = false;
};

// A threaded run never waits for labels, its first ones included: the frames before they come
// get no mask, and when they come, the refined mask of their own frame (0) is handed out once,
// on the square where it stood in frame 0. A single-thread run waits for them at frame 0.
TEST(MaskAhead, FirstLabelsLateInAThreadedRunGiveTheirFramesMaskOnce) {
  auto segmenter = std::make_unique<GatedSegmenter>();
  GatedSegmenter* gate = segmenter.get();
  SemanticSettings settings = Settings(100);
  settings.label_delay_frames = 0;
  MaskAhead stage(std::make_unique<SemanticFrontEnd>(std::move(segmenter), settings, RegionGrowingOptions{},
                                                     MaskRefineOptions{}, /*wait_for_due_labels=*/false),
                  WorkerMode::kThread);
  const TestFrame first = MakeFrame(0);
  stage.Submit(0, first.timestamp, first.bgr, first.depth_m);
  const MaskAheadResult unlabelled = stage.MaskFor(0, first.bgr, first.depth_m);
  EXPECT_EQ(unlabelled.mask.source_id, -1);
  EXPECT_TRUE(unlabelled.mask.mask.empty());
  EXPECT_EQ(unlabelled.mask.wait_ms, 0);
  EXPECT_EQ(unlabelled.mask.late_frame, -1);
  gate->Open();
  // The labels are taken when they are back, a frame or so later (bounded, not timed).
  int late_masks = 0, labelled_at = -1;
  for (int i = 1; i < 400 && (labelled_at < 0 || i <= labelled_at + 3); ++i) {
    const TestFrame f = MakeFrame(i % 20);  // the square keeps moving within the image
    stage.Submit(i, 100.0 + i, f.bgr, f.depth_m);
    const MaskAheadResult made = stage.MaskFor(i, f.bgr, f.depth_m);
    EXPECT_EQ(made.mask.wait_ms, 0) << i;
    if (made.mask.source_id >= 0 && labelled_at < 0) labelled_at = i;
    if (made.mask.late_frame < 0) continue;
    ++late_masks;
    EXPECT_EQ(made.mask.late_frame, 0);
    EXPECT_GE(made.mask.source_id, 0);  // 0's labels, or those of a frame labelled right after
    ASSERT_EQ(made.mask.late_mask.size(), first.bgr.size());
    EXPECT_GT(made.mask.late_mask.at<std::uint8_t>(55, 35), 0);    // frame 0's square
    EXPECT_EQ(made.mask.late_mask.at<std::uint8_t>(55, 130), 0);   // the wall beside it
  }
  EXPECT_GT(labelled_at, 0);
  EXPECT_EQ(late_masks, 1);
  stage.Stop();
}

TEST(MaskAhead, RequiresAFrontEnd) { EXPECT_THROW(MaskAhead(nullptr, WorkerMode::kInline), Error); }

}  // namespace
}  // namespace esdslam
