// esdslam synth: writes a deterministic synthetic RGB-D sequence (TUM layout, ground truth,
// mover masks, VOC labels, settings.yaml).
#include <cstdio>
#include <string>

#include <spdlog/spdlog.h>

#include "apps/esdslam/commands.h"
#include "common/timer.h"
#include "synth/sequence_writer.h"
#include "synth/synthetic_scene.h"

namespace esdslam::cli {
namespace {

struct SynthArgs {
  std::string preset = "dynamic";
  std::string out_dir;
  int frames = -1;
  long long seed = -1;
  int movers = -1;
  double depth_noise = -1;
  double turns = -1;
  double fps = -1;
  double readout = -1;  // seconds; < 0 = the preset's
};

int RunSynth(const SynthArgs& args) {
  SynthOptions options = SynthPreset(args.preset);
  if (args.frames >= 0) options.num_frames = args.frames;
  if (args.seed >= 0) options.seed = static_cast<std::uint32_t>(args.seed);
  if (args.movers >= 0) options.num_movers = args.movers;
  if (args.depth_noise >= 0) options.depth_noise_at_1m = args.depth_noise;
  if (args.turns > 0) options.loop_turns = args.turns;
  if (args.fps > 0) options.fps = args.fps;
  if (args.readout >= 0) options.readout_time_s = args.readout;
  options.Check();
  spdlog::info("synth: preset {} ({} trajectory, {} frames, {} movers, readout {} s, seed {}) -> {}", args.preset,
               options.trajectory, options.num_frames, options.num_movers, options.readout_time_s, options.seed,
               args.out_dir);
  const Stopwatch watch;
  const SyntheticScene scene(options);
  WriteSynthSequence(scene, args.out_dir, [&](int done, int total) {
    std::fprintf(stderr, "\rsynth: frame %d/%d (%.1f s)", done, total, watch.ElapsedMs() / 1000.0);
    if (done == total) std::fprintf(stderr, "\n");
  });
  spdlog::info("synth: wrote {} frames in {:.1f} s", options.num_frames, watch.ElapsedMs() / 1000.0);
  return 0;
}

RunFn SetupSynth(CLI::App& app) {
  auto args = std::make_shared<SynthArgs>();
  app.add_option("--preset", args->preset,
                 "static | dynamic | loop | orbit | corridor (loop-closing benchmark) | moved_box | occlusion (people "
                 "close to the camera, blocked sensor) | rolling (fast roll/pitch/yaw turns, rolling shutter with a "
                 "0.025 s readout)")
      ->check(CLI::IsMember({"static", "dynamic", "loop", "orbit", "corridor", "moved_box", "occlusion", "rolling"}))
      ->capture_default_str();
  app.add_option("--out", args->out_dir, "Output folder (TUM layout)")->required();
  app.add_option("--frames", args->frames, "Number of frames (default: preset's; static/dynamic 240, loop 450, rolling 180)")
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", args->seed, "Random seed of textures and movers (default 1)")->check(CLI::NonNegativeNumber);
  app.add_option("--movers", args->movers, "Number of moving people, 0..4 (default: preset's; dynamic 3)")
      ->check(CLI::Range(0, 4));
  app.add_option("--depth-noise", args->depth_noise,
                 "Depth noise sigma at 1 m in metres, grows with z^2 (default: preset's; orbit 0.008, corridor 0.003, "
                 "rolling 0.002, others 0)")
      ->check(CLI::Range(0.0, 0.05));
  app.add_option("--fps", args->fps,
                 "Frame rate (default 30; the path's duration stays frames / fps, except rolling's, whose motion "
                 "is a function of time; the readout must fit in a frame period)")
      ->check(CLI::Range(1.0, 120.0));
  app.add_option("--readout", args->readout,
                 "Rolling-shutter readout, seconds from the first to the last row, <= min(0.1, 1 / fps); 0 = global "
                 "shutter (default: preset's; rolling 0.025, others 0)")
      ->check(CLI::Range(0.0, 0.1));
  app.add_option("--turns", args->turns,
                 "loop / orbit / corridor: turns over the sequence (loop 1, orbit 1.35, corridor 1.3; with --frames "
                 "1 + 449 x turns the speed of one turn in 450 frames is kept)")
      ->check(CLI::Range(0.25, 3.0));
  return [args] { return RunSynth(*args); };
}

const Registrar kRegistrar({"synth", "Generate a synthetic RGB-D sequence with ground truth and mover masks", SetupSynth, 90});

}  // namespace
}  // namespace esdslam::cli
