// What the live viewer costs tracking (issue 15: at most 5 % of tracking throughput). The same
// synthetic sequence (`esdslam synth --preset dynamic`, held in memory, so disk reads do not
// blur the figure) runs through the run loop (system/run_loop.h) with the viewer off and on,
// back to back in one process, alternating the order in each pair (off-on, on-off, ...). With
// the viewer on, the frame callback offers every report to a LiveViewer that serves on a free
// port, and a client thread reads its event stream as a browser would. Throughput = frames /
// wall time of the run loop (frames per second); the ratio on/off of each pair, and their
// median, are printed on stdout.
//   build/benchmarks/viewer_bench [--pairs=N (5)] [--frames=N (120)] [--mode=geometry|none|full]
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "common/timer.h"
#include "io/memory_frame_source.h"
#include "io/tum_sequence.h"
#include "system/pipeline.h"
#include "system/run_config.h"
#include "system/run_loop.h"
#include "system/run_settings.h"
#include "viewer/live_viewer.h"
#include "viewer_sequence.h"

// Last: <resolv.h>, which cpp-httplib includes, defines _res, a name Eigen's headers use.
#include <httplib.h>

namespace esdslam {
namespace {

namespace fs = std::filesystem;

struct BenchArgs {
  int pairs = 5;
  int frames = 120;
  std::string mode = "geometry";  // no network: tracking is the bottleneck, the viewer's share is largest
};

// Reads the viewer's /events as a browser would, until the viewer closes the stream.
void ReadEvents(int port, std::atomic<long>* bytes) {
  httplib::Client client("127.0.0.1", port);
  client.Get("/events", [bytes](const char*, std::size_t size) {
    *bytes += static_cast<long>(size);
    return true;
  });
}

struct RunResult {
  double fps = 0;             // frames / wall time of the run loop
  double track_cpu_ms = 0;    // per frame: extraction + tracking (wall, from the reports)
  double viewer_cpu_ms = 0;   // per frame: the viewer thread's CPU time (frames + map)
};

// The run loop over the sequence, with or without the viewer.
RunResult RunOnce(const RunConfig& config, const std::vector<RgbdFrame>& frames, bool viewer_on) {
  Pipeline pipeline(config);
  std::unique_ptr<LiveViewer> viewer;
  std::thread browser;
  std::atomic<long> bytes{0};
  if (viewer_on) {
    ViewerOptions options;
    options.port = 0;
    viewer = std::make_unique<LiveViewer>(options, &pipeline.system(), pipeline.dense());
    const std::string url = viewer->url();
    const int port = std::atoi(url.c_str() + url.rfind(':') + 1);
    browser = std::thread(ReadEvents, port, &bytes);
  }
  MemoryFrameSource source(frames);
  RunResult result;
  Stopwatch clock;
  RunFrames(source, pipeline, [&](const FrameReport& report) {
    result.track_cpu_ms += report.track.extract_ms + report.track.track_ms;
    if (viewer) viewer->Offer(report);
  });
  const double seconds = clock.ElapsedMs() / 1000.0;
  const double n = static_cast<double>(frames.size());
  if (viewer) {
    const ViewerStats stats = viewer->stats();
    viewer->Close();  // ends the event stream
    browser.join();
    spdlog::info("viewer on: {} offered, {} skipped (interval), {} dropped (queue), {} frame events ({:.2f} ms CPU "
                 "each), {} map events ({:.1f} ms CPU each), {:.1f} MB streamed", stats.offered, stats.skipped,
                 stats.dropped, stats.encoded, stats.frame_cpu_ms / std::max(1L, stats.encoded), stats.maps,
                 stats.map_cpu_ms / std::max(1L, stats.maps), static_cast<double>(bytes.load()) / 1e6);
    result.viewer_cpu_ms = (stats.frame_cpu_ms + stats.map_cpu_ms) / n;
  }
  pipeline.StopSlam();
  result.fps = n / seconds;
  result.track_cpu_ms /= n;
  return result;
}

std::vector<RgbdFrame> MakeSequence(const BenchArgs& args, const std::string& dir) {
  WriteViewerBenchSequence(dir, args.frames);
  const TumSequence sequence = TumSequence::Open(dir);
  const RunSettings settings = LoadRunSettings(dir + "/settings.yaml");
  TumFolderSource folder(sequence.frames(), settings.core.depth_map_factor);
  std::vector<RgbdFrame> frames;
  while (std::optional<RgbdFrame> frame = folder.Next()) frames.push_back(std::move(*frame));
  return frames;
}

BenchArgs ParseArgs(int argc, char** argv) {
  BenchArgs args;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--pairs=", 0) == 0) args.pairs = std::max(1, std::atoi(arg.c_str() + 8));
    else if (arg.rfind("--frames=", 0) == 0) args.frames = std::max(30, std::atoi(arg.c_str() + 9));
    else if (arg.rfind("--mode=", 0) == 0) args.mode = arg.substr(7);
    else spdlog::warn("viewer_bench: ignoring {}", arg);
  }
  return args;
}

int Main(int argc, char** argv) {
  const BenchArgs args = ParseArgs(argc, argv);
  fs::current_path(ESDSLAM_SOURCE_DIR);  // the settings' model and vocabulary paths are relative to it
  const std::string dir = (fs::temp_directory_path() / ("esdslam_viewer_bench_" + std::to_string(::getpid()))).string();
  const std::vector<RgbdFrame> frames = MakeSequence(args, dir + "/seq");
  RunFlags flags;
  flags.run.sequence_dir = dir + "/seq";
  flags.run.out_dir = dir + "/out";
  flags.mode = ParseDynamicMode(args.mode);
  const RunConfig config = ResolveRunConfig(LoadRunSettings(dir + "/seq/settings.yaml"), flags);
  std::vector<double> ratios;
  double viewer_cpu = 0, track_ms = 0;
  std::printf("pair  order   off_fps  on_fps  on/off  viewer_cpu_ms/frame  track_ms/frame\n");
  for (int pair = 0; pair < args.pairs; ++pair) {
    const bool on_first = pair % 2 == 1;
    const RunResult first = RunOnce(config, frames, on_first);
    const RunResult second = RunOnce(config, frames, !on_first);
    const RunResult& off = on_first ? second : first;
    const RunResult& on = on_first ? first : second;
    ratios.push_back(on.fps / off.fps);
    viewer_cpu += on.viewer_cpu_ms / args.pairs;
    track_ms += off.track_cpu_ms / args.pairs;
    std::printf("%4d  %s  %7.2f  %6.2f  %6.3f  %19.2f  %14.2f\n", pair, on_first ? "on-off" : "off-on", off.fps, on.fps,
                on.fps / off.fps, on.viewer_cpu_ms, off.track_cpu_ms);
    std::fflush(stdout);
  }
  std::vector<double> sorted = ratios;
  std::sort(sorted.begin(), sorted.end());
  double mean = 0;
  for (const double r : ratios) mean += r / static_cast<double>(ratios.size());
  std::printf("throughput ratio viewer on/off: median %.3f, mean %.3f over %zu pairs (%d frames, mode %s)\n",
              sorted[sorted.size() / 2], mean, ratios.size(), args.frames, args.mode.c_str());
  std::printf("viewer thread CPU %.2f ms per frame = %.1f %% of the tracking step (%.2f ms per frame)\n", viewer_cpu,
              100.0 * viewer_cpu / std::max(1e-9, track_ms), track_ms);
  fs::remove_all(dir);
  return 0;
}

}  // namespace
}  // namespace esdslam

int main(int argc, char** argv) {
  spdlog::set_default_logger(spdlog::stderr_color_mt("viewer_bench"));  // logs to stderr, results to stdout
  try {
    return esdslam::Main(argc, argv);
  } catch (const std::exception& e) {
    spdlog::error("viewer_bench: {}", e.what());
    return 1;
  }
}
