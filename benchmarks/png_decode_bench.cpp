// Image loading (issue 12 item 5): cv::imread against io/png_decoder.h on the PNGs of a folder,
// alternating per file so that a noisy machine loads both alike. Prints the mean CPU time of the
// calling thread per file for each, their ratio, and how many files decoded differently (must be 0).
//
//   build/benchmarks/png_decode_bench ../shared/data/bonn_crowd_dev/rgb ../shared/data/bonn_crowd_dev/depth
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/timer.h"
#include "io/png_decoder.h"

namespace {

bool Same(const cv::Mat& a, const cv::Mat& b) {
  return a.type() == b.type() && a.size() == b.size() && (a.empty() || cv::norm(a, b, cv::NORM_INF) == 0);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: png_decode_bench FOLDER [FOLDER ...]\n");
    return 2;
  }
  for (int arg = 1; arg < argc; ++arg) {
    std::vector<std::string> files;
    for (const auto& entry : std::filesystem::directory_iterator(argv[arg]))
      if (entry.path().extension() == ".png") files.push_back(entry.path().string());
    if (files.empty()) {
      std::fprintf(stderr, "%s: no .png files\n", argv[arg]);
      return 2;
    }
    double opencv_ms = 0.0, ours_ms = 0.0;
    int differing = 0;
    for (const std::string& file : files) {
      esdslam::ThreadCpuStopwatch cpu;
      const cv::Mat reference = cv::imread(file, cv::IMREAD_UNCHANGED);
      opencv_ms += cpu.ElapsedMs();
      cpu.Restart();
      const cv::Mat decoded = esdslam::ReadImageUnchanged(file);
      ours_ms += cpu.ElapsedMs();
      if (!Same(reference, decoded)) ++differing;
    }
    const double n = static_cast<double>(files.size());
    std::printf("%s: %zu files; cv::imread %.2f ms, ReadImageUnchanged %.2f ms CPU per file (ratio %.2f); "
                "%d decoded differently\n",
                argv[arg], files.size(), opencv_ms / n, ours_ms / n, ours_ms / opencv_ms, differing);
    if (differing > 0) return 1;
  }
  return 0;
}
