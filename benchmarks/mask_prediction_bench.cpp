// Mask prediction between network frames (issue 12): how well each candidate carries the labels
// of frame s to frame s + age, for age 1..max_age, and what it costs per frame.
//
//   mask_prediction_bench [--synth DIR] [--real DIR --labels DIR] [--max-age N] [--source-step S]
//                         [--candidates "NAME=KIND[:KEY=VALUE,...];..."]   (see MakeCandidate)
//
// --synth: a sequence written by `esdslam synth --preset dynamic --out DIR`; the labels carried
//   are its perfect VOC labels (labels/), the truth its mover masks (masks/).
// --real:  a TUM-layout sequence (e.g. ../shared/data/bonn_crowd_dev) with network labels of
//   every frame in --labels DIR/<rgb file name> (class ids, 15 = person); the truth of frame j
//   is the network's own fresh person labels of frame j.
// Every S-th frame is a source. For each candidate and age it prints the mean IoU of the raw
// carried person mask against the truth, the mean IoU of the refined one (region growing on frame
// j's depth plus the carried mask's core, as SemanticFrontEnd::MaskFor does) against the refined
// truth (synthetic: the truth itself; real: the fresh labels refined the same way, i.e. the mask
// every-frame labels would give), and the recall of the truth pixels (pooled over frames) by the
// refined mask. Frames where truth and prediction are both empty are not counted. CPU time: thread
// CPU time of advancing one frame and predicting, mean per frame (one OpenCV thread); then the CPU
// time of labels that arrive late, and the predictor's uncovered fraction and trust by age.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "common/error.h"
#include "common/timer.h"
#include "dynamic/region_growing.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "mask_candidates.h"

namespace esdslam::bench {
namespace {
namespace fs = std::filesystem;

const char* kDefaultCandidates =
    "hold=hold;camera=camera;keypoints=keypoints;flow-plain=flow:occ=0,fill=0,clean=0;flow-nomem=flow:mem=0;"
    "flow-nofill=flow:fill=0;flow=flow;flow+dil=flow:dil=0.5";

struct Args {
  std::string synth_dir, real_dir, labels_dir;
  int max_age = 20;
  int source_step = 2;
  std::string candidates = kDefaultCandidates;
};

struct Sequence {
  std::string name;
  std::vector<FrameEntry> frames;
  std::vector<Rigid3> poses;  // ground truth at each frame (nearest stamp)
  std::string labels_dir, truth_dir;  // truth_dir empty: truth = fresh labels
  PinholeCamera camera;
};

Sequence OpenSequence(const std::string& dir, const std::string& labels_dir, bool synthetic) {
  Sequence seq;
  seq.name = fs::path(dir).filename().string();
  seq.frames = TumSequence::Open(dir).frames();
  const std::vector<StampedPose> truth = ReadTumTrajectory(dir + "/groundtruth.txt");
  for (const FrameEntry& frame : seq.frames) {
    auto it = std::lower_bound(truth.begin(), truth.end(), frame.timestamp,
                               [](const StampedPose& p, double t) { return p.timestamp < t; });
    if (it == truth.end() || (it != truth.begin() && frame.timestamp - std::prev(it)->timestamp < it->timestamp - frame.timestamp))
      it = std::prev(it);
    seq.poses.push_back(it->world_from_cam);
  }
  seq.labels_dir = synthetic ? dir + "/labels" : labels_dir;
  if (synthetic) seq.truth_dir = dir + "/masks";
  CameraIntrinsics intrinsics;
  if (synthetic) {
    intrinsics.fx = intrinsics.fy = 525.0;
    intrinsics.cx = 319.5;
    intrinsics.cy = 239.5;
  } else {  // Bonn (../shared/README.md); distortion is ignored by the warp
    intrinsics.fx = 542.822841;
    intrinsics.fy = 542.576870;
    intrinsics.cx = 315.593520;
    intrinsics.cy = 237.756098;
  }
  seq.camera = PinholeCamera(intrinsics);
  return seq;
}

cv::Mat ReadImage(const std::string& path, int flags) {
  cv::Mat image = cv::imread(path, flags);
  if (image.empty()) throw Error("cannot read " + path);
  return image;
}

// As SemanticFrontEnd::MaskFor (without its final safety dilation): region growing from the
// mask on the current depth, plus the mask's interior (eroded by 3 px).
cv::Mat Refine(const cv::Mat& mask, const cv::Mat& depth_m) {
  cv::Mat refined = RefineDynamicMask(mask, depth_m, RegionGrowingOptions{});
  cv::Mat core;
  cv::erode(mask, core, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(7, 7)));
  refined.setTo(255, core);
  return refined;
}

// Frames loaded on demand and dropped once no source needs them.
class FrameCache {
 public:
  explicit FrameCache(const Sequence& seq) : seq_(seq) {}
  const FrameData& Get(int i) {
    auto it = frames_.find(i);
    if (it != frames_.end()) return it->second;
    const FrameEntry& entry = seq_.frames[static_cast<std::size_t>(i)];
    const std::string name = fs::path(entry.rgb_path).filename().string();
    FrameData frame;
    frame.grey = ReadImage(entry.rgb_path, cv::IMREAD_GRAYSCALE);
    ReadImage(entry.depth_path, cv::IMREAD_UNCHANGED).convertTo(frame.depth_m, CV_32F, 1.0 / 5000.0);
    frame.labels = ReadImage(seq_.labels_dir + "/" + name, cv::IMREAD_UNCHANGED);
    frame.truth = seq_.truth_dir.empty() ? PersonMask(frame.labels)
                                         : ReadImage(seq_.truth_dir + "/" + name, cv::IMREAD_UNCHANGED) != 0;
    frame.world_from_cam = seq_.poses[static_cast<std::size_t>(i)];
    frame.truth_refined = seq_.truth_dir.empty() ? Refine(frame.truth, frame.depth_m) : frame.truth;
    return frames_.emplace(i, std::move(frame)).first->second;
  }
  void DropBefore(int i) { frames_.erase(frames_.begin(), frames_.lower_bound(i)); }

 private:
  const Sequence& seq_;
  std::map<int, FrameData> frames_;
};

struct AgeStats {
  double iou_raw = 0, iou_refined = 0;
  int frames = 0;  // frames where truth or prediction is non-empty
  double truth_px = 0, covered_px = 0;
  double uncovered = 0, trust = 0;
  int samples = 0;  // predictions with an uncovered fraction and trust
};

struct CandidateStats {
  std::vector<AgeStats> by_age;
  double cpu_ms = 0;
  int steps = 0;
};

double IoU(const cv::Mat& a, const cv::Mat& b, bool* any) {
  const int uni = cv::countNonZero(a | b);
  *any = uni > 0;
  return uni == 0 ? 1.0 : cv::countNonZero(a & b) / static_cast<double>(uni);
}

void Score(const cv::Mat& predicted, const FrameData& frame, AgeStats& stats) {
  bool any = false;
  const double iou_raw = IoU(predicted != 0, frame.truth, &any);
  if (!any) return;
  const cv::Mat refined = Refine(predicted, frame.depth_m);
  bool unused = false;
  stats.iou_raw += iou_raw;
  stats.iou_refined += IoU(refined, frame.truth_refined, &unused);
  ++stats.frames;
  stats.truth_px += cv::countNonZero(frame.truth);
  stats.covered_px += cv::countNonZero(frame.truth & refined);
}

// A candidate from "NAME=KIND[:KEY=VALUE,...]": KIND hold | camera | keypoints | flow; flow keys
// (MaskPredictorOptions): w flow_width_px, fs flow_finest_scale, ps flow_patch_size, st
// flow_patch_stride, gd flow_gradient_iterations, vr flow_variational_iterations, occ
// disocclusion.occlusion_abs_tolerance_m, fill disocclusion.fill_abs_tolerance_m, mem
// disocclusion.depth_memory_frames, clean
// cleanup_radius_px, dil age_dilation_px_per_frame.
std::unique_ptr<Candidate> MakeCandidate(const std::string& spec, const Sequence& seq, cv::Size size) {
  const std::size_t eq = spec.find('=');
  if (eq == std::string::npos) throw Error("candidate '" + spec + "': expected NAME=KIND[:KEY=VALUE,...]");
  const std::string name = spec.substr(0, eq);
  const std::size_t colon = spec.find(':', eq);
  const std::string kind = spec.substr(eq + 1, colon == std::string::npos ? std::string::npos : colon - eq - 1);
  if (kind == "hold") return std::make_unique<HoldCandidate>();
  if (kind == "camera") return std::make_unique<CameraCandidate>(seq.camera);
  if (kind == "keypoints") return std::make_unique<KeypointCandidate>();
  if (kind != "flow") throw Error("candidate '" + spec + "': unknown kind " + kind);
  MaskPredictorOptions o;
  std::stringstream keys(colon == std::string::npos ? "" : spec.substr(colon + 1));
  for (std::string item; std::getline(keys, item, ',');) {
    const std::size_t e = item.find('=');
    if (e == std::string::npos) throw Error("candidate '" + spec + "': expected KEY=VALUE, got " + item);
    const std::string key = item.substr(0, e), value = item.substr(e + 1);
    if (key == "w") o.flow_width_px = std::stoi(value);
    else if (key == "fs") o.flow_finest_scale = std::stoi(value);
    else if (key == "ps") o.flow_patch_size = std::stoi(value);
    else if (key == "st") o.flow_patch_stride = std::stoi(value);
    else if (key == "gd") o.flow_gradient_iterations = std::stoi(value);
    else if (key == "vr") o.flow_variational_iterations = std::stoi(value);
    else if (key == "occ") o.disocclusion.occlusion_abs_tolerance_m = std::stod(value);
    else if (key == "fill") o.disocclusion.fill_abs_tolerance_m = std::stod(value);
    else if (key == "mem") o.disocclusion.depth_memory_frames = std::stoi(value);
    else if (key == "clean") o.cleanup_radius_px = std::stoi(value);
    else if (key == "dil") o.age_dilation_px_per_frame = std::stod(value);
    else throw Error("candidate '" + spec + "': unknown key or value " + item);
  }
  return std::make_unique<FlowCandidate>(name, size, o);
}

std::vector<std::unique_ptr<Candidate>> MakeCandidates(const std::string& specs, const Sequence& seq, cv::Size size) {
  std::vector<std::unique_ptr<Candidate>> out;
  std::stringstream list(specs);
  for (std::string spec; std::getline(list, spec, ';');) {
    if (!spec.empty()) out.push_back(MakeCandidate(spec, seq, size));
  }
  if (out.empty()) throw Error("no candidates");
  return out;
}

// Thread CPU time of AddLabels for labels that arrive `age` frames late (carried through the
// stored flows at once), default options, mean over the sequence.
void PrintLateLabelCost(const Sequence& seq, FrameCache& cache) {
  std::printf("\n%s, CPU time of late labels (default options): AddLabels of frame j - age at frame j\n\n"
              "| age | ms |\n|---|---|\n", seq.name.c_str());
  const int last = static_cast<int>(seq.frames.size()) - 1;
  for (int age : {2, 5, 10, 20}) {
    if (age > last) continue;
    double cpu_ms = 0;
    int runs = 0;
    for (int j = age; j <= last; j += std::max(1, last / 10)) {
      cache.DropBefore(j - age);
      MaskPredictor predictor(cache.Get(j).grey.size());
      for (int k = j - age; k <= j; ++k) predictor.AddFrame(k, cache.Get(k).grey, cache.Get(k).depth_m);
      ThreadCpuStopwatch cpu;
      predictor.AddLabels(j - age, cache.Get(j - age).labels);
      cpu_ms += cpu.ElapsedMs();
      ++runs;
    }
    std::printf("| %d | %.2f |\n", age, cpu_ms / std::max(1, runs));
  }
}

using Candidates = std::vector<std::unique_ptr<Candidate>>;

// Every source frame's labels carried by every candidate to ages 1..max_age.
std::vector<CandidateStats> Measure(const Sequence& seq, const Args& args, FrameCache& cache, Candidates& candidates) {
  std::vector<CandidateStats> stats(candidates.size());
  for (auto& s : stats) s.by_age.resize(static_cast<std::size_t>(args.max_age) + 1);
  const int last_source = static_cast<int>(seq.frames.size()) - 1 - args.max_age;
  for (int source = 0; source <= last_source; source += args.source_step) {
    cache.DropBefore(source);
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      Candidate& candidate = *candidates[c];
      candidate.Start(cache.Get(source));
      Score(candidate.Predict(), cache.Get(source), stats[c].by_age[0]);
      for (int age = 1; age <= args.max_age; ++age) {
        const FrameData& frame = cache.Get(source + age);
        ThreadCpuStopwatch cpu;
        candidate.Advance(frame);
        const cv::Mat predicted = candidate.Predict();
        stats[c].cpu_ms += cpu.ElapsedMs();
        ++stats[c].steps;
        AgeStats& at = stats[c].by_age[static_cast<std::size_t>(age)];
        Score(predicted, frame, at);
        if (const auto* flow = dynamic_cast<const FlowCandidate*>(&candidate)) {
          at.uncovered += flow->last().uncovered_fraction;
          at.trust += flow->last().trust;
          ++at.samples;
        }
      }
    }
    std::fprintf(stderr, "\r%s: source %d/%d", seq.name.c_str(), source, last_source);
  }
  std::fprintf(stderr, "\n");
  return stats;
}

void PrintAccuracy(const Sequence& seq, const Args& args, const Candidates& candidates,
                   const std::vector<CandidateStats>& stats) {
  const char* titles[] = {"IoU of the raw carried mask", "IoU after refinement (region growing + core)",
                          "recall of the truth pixels after refinement"};
  for (int table = 0; table < 3; ++table) {
    std::printf("\n%s, %s (sources every %d frames)\n\n| age |", seq.name.c_str(), titles[table], args.source_step);
    for (const auto& c : candidates) std::printf(" %s |", c->Name().c_str());
    std::printf("\n|---|");
    for (std::size_t c = 0; c < candidates.size(); ++c) std::printf("---|");
    for (int age = 0; age <= args.max_age; ++age) {
      std::printf("\n| %d |", age);
      for (const auto& s : stats) {
        const AgeStats& a = s.by_age[static_cast<std::size_t>(age)];
        const double value = table == 0   ? a.iou_raw / std::max(1, a.frames)
                             : table == 1 ? a.iou_refined / std::max(1, a.frames)
                                          : a.covered_px / std::max(1.0, a.truth_px);
        std::printf(" %.3f |", value);
      }
    }
    std::printf("\n");
  }
  std::printf("\n%s, CPU time per frame (advance + predict, thread CPU time)\n\n| candidate | ms |\n|---|---|\n",
              seq.name.c_str());
  for (std::size_t c = 0; c < candidates.size(); ++c)
    std::printf("| %s | %.2f |\n", candidates[c]->Name().c_str(), stats[c].cpu_ms / std::max(1, stats[c].steps));
}

// The trust of the candidate named "flow" (the default options), else of the first flow candidate.
void PrintTrust(const Sequence& seq, const Args& args, const Candidates& candidates,
                const std::vector<CandidateStats>& stats) {
  std::size_t flow = 0;
  while (flow + 1 < candidates.size() && !dynamic_cast<const FlowCandidate*>(candidates[flow].get())) ++flow;
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    if (candidates[c]->Name() == "flow") flow = c;
  }
  std::printf("\n%s, %s: mean uncovered fraction and trust by age\n\n| age | uncovered | trust |\n|---|---|---|\n",
              seq.name.c_str(), candidates[flow]->Name().c_str());
  for (int age = 1; age <= args.max_age; ++age) {
    const AgeStats& a = stats[flow].by_age[static_cast<std::size_t>(age)];
    std::printf("| %d | %.3f | %.2f |\n", age, a.uncovered / std::max(1, a.samples), a.trust / std::max(1, a.samples));
  }
}

void Evaluate(const Sequence& seq, const Args& args) {
  FrameCache cache(seq);
  Candidates candidates = MakeCandidates(args.candidates, seq, cache.Get(0).grey.size());
  const std::vector<CandidateStats> stats = Measure(seq, args, cache, candidates);
  PrintAccuracy(seq, args, candidates, stats);
  PrintLateLabelCost(seq, cache);  // after the measurement: it reloads frames
  PrintTrust(seq, args, candidates, stats);
}

Args Parse(int argc, char** argv) {
  Args args;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) throw Error("missing value after " + flag);
    const std::string value = argv[++i];
    if (flag == "--synth") args.synth_dir = value;
    else if (flag == "--real") args.real_dir = value;
    else if (flag == "--labels") args.labels_dir = value;
    else if (flag == "--max-age") args.max_age = std::stoi(value);
    else if (flag == "--source-step") args.source_step = std::stoi(value);
    else if (flag == "--candidates") args.candidates = value;
    else throw Error("unknown flag " + flag);
  }
  if (args.max_age < 1 || args.source_step < 1) throw Error("--max-age and --source-step must be >= 1");
  if (!args.real_dir.empty() && args.labels_dir.empty()) throw Error("--real needs --labels");
  return args;
}

}  // namespace
}  // namespace esdslam::bench

int main(int argc, char** argv) {
  try {
    cv::setNumThreads(1);
    const esdslam::bench::Args args = esdslam::bench::Parse(argc, argv);
    if (!args.synth_dir.empty()) esdslam::bench::Evaluate(esdslam::bench::OpenSequence(args.synth_dir, "", true), args);
    if (!args.real_dir.empty())
      esdslam::bench::Evaluate(esdslam::bench::OpenSequence(args.real_dir, args.labels_dir, false), args);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mask_prediction_bench: %s\n", e.what());
    return 1;
  }
}
