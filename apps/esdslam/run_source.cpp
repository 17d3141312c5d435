#include "apps/esdslam/run_source.h"

#include <algorithm>
#include <optional>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>

#include "common/error.h"
#include "device/openni_source.h"
#include "io/live_playback_source.h"
#include "io/prefetching_source.h"
#include "io/playback_clock.h"
#include "io/tum_sequence.h"

namespace esdslam::cli {
namespace {

// The first `limit` frames of a source whose length is not known in advance.
class FirstFrames final : public FrameSource {
 public:
  FirstFrames(std::unique_ptr<FrameSource> source, std::size_t limit) : source_(std::move(source)), limit_(limit) {}
  std::optional<RgbdFrame> Next() override {
    if (returned_ == limit_) return std::nullopt;
    std::optional<RgbdFrame> frame = source_->Next();
    if (frame) ++returned_;
    return frame;
  }
  std::optional<std::size_t> frame_count() const override {
    const std::optional<std::size_t> n = source_->frame_count();
    return n ? std::min(*n, limit_) : std::optional<std::size_t>(limit_);
  }

 private:
  std::unique_ptr<FrameSource> source_;
  const std::size_t limit_;
  std::size_t returned_ = 0;
};

std::unique_ptr<FrameSource> PlayLive(std::unique_ptr<FrameSource> source) {
  return std::make_unique<LivePlaybackSource>(std::move(source), std::make_shared<SteadyPlaybackClock>());
}

RunSource OpenCamera(const RunOptions& run, const CameraArgs& camera, Settings* settings) {
  OpenNiOptions options;
  options.uri = camera.uri;
  options.width = settings->camera.width;
  options.height = settings->camera.height;
  options.fps = std::max(1, static_cast<int>(settings->fps + 0.5));
  options.registration = ParseDepthRegistration(camera.registration);
  std::unique_ptr<OpenNiSource> device = OpenOpenNiSource(options);
  const DeviceCameraInfo info = device->info();
  *settings = SettingsForDevice(*settings, info, ParseCameraModelFrom(camera.model_from));
  spdlog::info("camera: {} ({}), colour {}x{} at {} fps, registration {}", info.uri,
               info.recording ? "recording" : "live device", info.colour.width, info.colour.height, info.colour.fps,
               options.registration == DepthRegistration::kOff ? "off"
               : info.hardware_registration                     ? "by the device"
                                                                : "in software (field-of-view models)");
  if (run.live && !info.recording) throw Error("--live plays a recording on its clock; a camera is live already");
  RunSource input;
  input.total_frames = device->frame_count().value_or(0);
  input.source = std::move(device);
  if (run.live) input.source = PlayLive(std::move(input.source));
  if (run.max_frames > 0) {
    input.source = std::make_unique<FirstFrames>(std::move(input.source), run.max_frames);
    input.total_frames = input.total_frames > 0 ? std::min<std::size_t>(input.total_frames, run.max_frames)
                                                : static_cast<std::size_t>(run.max_frames);
  }
  return input;
}

}  // namespace

RunSource OpenRunSource(const RunOptions& run, const CameraArgs& camera, int max_consecutive_bad_frames,
                        Settings* settings) {
  if (camera.use) return OpenCamera(run, camera, settings);
  AssociationOptions associations;
  associations.association_file = run.associations;
  const TumSequence sequence = TumSequence::Open(run.sequence_dir, associations);
  std::size_t n = sequence.frames().size();
  if (run.max_frames > 0) n = std::min<std::size_t>(n, run.max_frames);
  std::vector<FrameEntry> frames(sequence.frames().begin(), sequence.frames().begin() + n);
  RunSource input;
  input.total_frames = n;
  if (sequence.has_groundtruth()) input.groundtruth_path = sequence.groundtruth_path();
  FolderSourceOptions options;
  options.max_consecutive_bad_frames = max_consecutive_bad_frames;
  options.image_size = {settings->camera.width, settings->camera.height};
  auto folder = std::make_unique<TumFolderSource>(std::move(frames), settings->depth_map_factor, options);
  input.folder = folder.get();
  // PNGs decoded ahead on a loader thread, off the tracking thread (timing.csv load_ms is then
  // the wait for a decoded frame).
  input.source = std::make_unique<PrefetchingFrameSource>(std::move(folder));
  if (run.live) input.source = PlayLive(std::move(input.source));
  return input;
}

}  // namespace esdslam::cli
