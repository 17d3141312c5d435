#include "device/openni_source.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <optional>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "device/rgbd_conversion.h"

#if ESDSLAM_HAVE_OPENNI2
#include <OpenNI.h>
#endif

namespace esdslam {

DepthRegistration ParseDepthRegistration(const std::string& text) {
  if (text == "device") return DepthRegistration::kDevice;
  if (text == "off") return DepthRegistration::kOff;
  throw Error("depth registration must be 'device' or 'off', got '" + text + "'");
}

void OpenNiOptions::Check() const {
  if (width <= 0 || height <= 0 || width > 8192 || height > 8192)
    throw Error(fmt::format("camera: video mode {}x{} must be 1..8192 pixels each way", width, height));
  if (fps <= 0 || fps > 1000) throw Error(fmt::format("camera: fps must be in 1..1000, got {}", fps));
  if (frame_timeout_ms <= 0 || frame_timeout_ms > 600000)
    throw Error(fmt::format("camera: frame timeout must be in 1..600000 ms, got {}", frame_timeout_ms));
}

namespace {

bool IsRecording(const std::string& uri) {
  std::string extension = std::filesystem::path(uri).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".oni";
}

}  // namespace

#if ESDSLAM_HAVE_OPENNI2
namespace {

std::string OniError() { return openni::OpenNI::getExtendedError(); }

// OpenNI2's process-wide state, initialised for the source's lifetime.
struct OniRuntime {
  OniRuntime() {
    if (openni::OpenNI::initialize() != openni::STATUS_OK)
      throw Error("camera: OpenNI2 initialisation failed: " + OniError());
  }
  ~OniRuntime() { openni::OpenNI::shutdown(); }
  OniRuntime(const OniRuntime&) = delete;
  OniRuntime& operator=(const OniRuntime&) = delete;
};

DeviceStreamInfo StreamInfo(const openni::VideoStream& stream) {
  const openni::VideoMode mode = stream.getVideoMode();
  return {mode.getResolutionX(), mode.getResolutionY(), static_cast<double>(mode.getFps()),
          stream.getHorizontalFieldOfView(), stream.getVerticalFieldOfView()};
}

class OpenNi2Source final : public OpenNiSource {
 public:
  explicit OpenNi2Source(const OpenNiOptions& options);
  ~OpenNi2Source() override;
  std::optional<RgbdFrame> Next() override;
  std::optional<std::size_t> frame_count() const override { return frame_count_; }
  const DeviceCameraInfo& info() const override { return info_; }

 private:
  void Open(const std::string& uri);
  void StartStream(openni::VideoStream& stream, openni::SensorType sensor, openni::PixelFormat format,
                   const OpenNiOptions& options, const char* name);
  void SetUpRegistration(const OpenNiOptions& options);
  openni::VideoFrameRef Read(openni::VideoStream& stream, const char* name);
  cv::Mat DepthImage(const openni::VideoFrameRef& depth) const;

  OniRuntime runtime_;  // first: initialised before and shut down after the device
  openni::Device device_;
  openni::VideoStream colour_, depth_;
  DeviceCameraInfo info_;
  bool software_registration_ = false;
  Rigid3 colour_from_depth_;
  int timeout_ms_;
  int last_index_ = -1;                     // the colour frame number returned last
  std::optional<std::size_t> frame_count_;  // recordings: colour frames in the file
  std::size_t returned_ = 0;
};

OpenNi2Source::OpenNi2Source(const OpenNiOptions& options) : timeout_ms_(options.frame_timeout_ms) {
  Open(options.uri);
  StartStream(colour_, openni::SENSOR_COLOR, openni::PIXEL_FORMAT_RGB888, options, "colour");
  StartStream(depth_, openni::SENSOR_DEPTH, openni::PIXEL_FORMAT_DEPTH_1_MM, options, "depth");
  info_.colour = StreamInfo(colour_);
  info_.depth = StreamInfo(depth_);
  info_.colour.Check("colour");
  info_.depth.Check("depth");
  SetUpRegistration(options);
  device_.setDepthColorSyncEnabled(true);  // best effort: recordings and some devices refuse
  if (info_.recording) {
    openni::PlaybackControl* playback = device_.getPlaybackControl();
    playback->setSpeed(-1.0f);  // "manual": the next frame when we read it
    playback->setRepeatEnabled(false);
    frame_count_ = static_cast<std::size_t>(std::max(0, playback->getNumberOfFrames(colour_)));
  }
}

OpenNi2Source::~OpenNi2Source() {
  colour_.stop();
  depth_.stop();
  colour_.destroy();
  depth_.destroy();
  device_.close();
}

void OpenNi2Source::Open(const std::string& uri) {
  info_.recording = IsRecording(uri);
  if (uri.empty()) {
    openni::Array<openni::DeviceInfo> devices;
    openni::OpenNI::enumerateDevices(&devices);
    if (devices.getSize() == 0)
      throw Error("camera: no OpenNI2 device attached. Plug in a Kinect, Xtion or Orbbec-class sensor (check "
                  "`lsusb` and that this user may open it), or play a recording: --camera FILE.oni");
  }
  if (device_.open(uri.empty() ? openni::ANY_DEVICE : uri.c_str()) != openni::STATUS_OK)
    throw Error(fmt::format("camera: cannot open OpenNI2 device '{}': {}", uri.empty() ? "(first attached)" : uri,
                            OniError()));
  info_.uri = device_.getDeviceInfo().getUri();
}

void OpenNi2Source::StartStream(openni::VideoStream& stream, openni::SensorType sensor, openni::PixelFormat format,
                                const OpenNiOptions& options, const char* name) {
  if (!device_.hasSensor(sensor)) throw Error(fmt::format("camera {}: the device has no {} sensor", info_.uri, name));
  if (stream.create(device_, sensor) != openni::STATUS_OK)
    throw Error(fmt::format("camera {}: cannot create the {} stream: {}", info_.uri, name, OniError()));
  if (!info_.recording) {  // a recording plays the mode it was recorded in
    openni::VideoMode mode;
    mode.setResolution(options.width, options.height);
    mode.setFps(options.fps);
    mode.setPixelFormat(format);
    if (stream.setVideoMode(mode) != openni::STATUS_OK)
      throw Error(fmt::format("camera {}: the {} stream cannot deliver {}x{} at {} fps: {}", info_.uri, name,
                              options.width, options.height, options.fps, OniError()));
  }
  if (stream.getVideoMode().getPixelFormat() != format)
    throw Error(fmt::format("camera {}: the {} stream's pixel format is not {}", info_.uri, name,
                            format == openni::PIXEL_FORMAT_RGB888 ? "RGB888" : "depth in 1 mm"));
  if (stream.start() != openni::STATUS_OK)
    throw Error(fmt::format("camera {}: cannot start the {} stream: {}", info_.uri, name, OniError()));
}

void OpenNi2Source::SetUpRegistration(const OpenNiOptions& options) {
  if (options.registration == DepthRegistration::kOff) return;
  const auto mode = openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR;
  info_.hardware_registration =
      device_.isImageRegistrationModeSupported(mode) && device_.setImageRegistrationMode(mode) == openni::STATUS_OK;
  software_registration_ = !info_.hardware_registration;
  colour_from_depth_ = options.colour_from_depth;
}

openni::VideoFrameRef OpenNi2Source::Read(openni::VideoStream& stream, const char* name) {
  openni::VideoStream* streams[] = {&stream};
  int ready = -1;
  if (openni::OpenNI::waitForAnyStream(streams, 1, &ready, timeout_ms_) != openni::STATUS_OK)
    throw Error(fmt::format("camera {}: no {} frame for {} ms (unplugged?): {}", info_.uri, name, timeout_ms_,
                            OniError()));
  openni::VideoFrameRef frame;
  if (stream.readFrame(&frame) != openni::STATUS_OK || !frame.isValid())
    throw Error(fmt::format("camera {}: cannot read a {} frame: {}", info_.uri, name, OniError()));
  return frame;
}

cv::Mat OpenNi2Source::DepthImage(const openni::VideoFrameRef& depth) const {
  cv::Mat depth_m = DepthMmToMetres(static_cast<const std::uint16_t*>(depth.getData()), depth.getWidth(),
                                    depth.getHeight(), static_cast<std::size_t>(depth.getStrideInBytes()));
  const cv::Size colour_size(info_.colour.width, info_.colour.height);
  if (software_registration_)
    return RegisterDepthToColour(depth_m, IntrinsicsFromFieldOfView(info_.depth), IntrinsicsFromFieldOfView(info_.colour),
                                 colour_from_depth_);
  // Hardware-registered (or unregistered) depth on the colour image's grid, maybe at another size.
  if (depth_m.size() != colour_size) cv::resize(depth_m, depth_m, colour_size, 0, 0, cv::INTER_NEAREST);
  return depth_m;
}

std::optional<RgbdFrame> OpenNi2Source::Next() {
  if (frame_count_ && returned_ >= *frame_count_) return std::nullopt;
  const openni::VideoFrameRef colour = Read(colour_, "colour");
  const openni::VideoFrameRef depth = Read(depth_, "depth");
  RgbdFrame frame;
  frame.timestamp = 1e-6 * static_cast<double>(colour.getTimestamp());  // device microseconds
  frame.bgr = Rgb888ToBgr(static_cast<const std::uint8_t*>(colour.getData()), colour.getWidth(), colour.getHeight(),
                          static_cast<std::size_t>(colour.getStrideInBytes()));
  frame.depth_m = DepthImage(depth);
  const int index = colour.getFrameIndex();
  if (last_index_ >= 0 && index > last_index_ + 1) frame.dropped_before = index - last_index_ - 1;
  last_index_ = index;
  ++returned_;
  return frame;
}

}  // namespace

bool HaveOpenNi() { return true; }

namespace {
std::unique_ptr<OpenNiSource> MakeOpenNiSource(const OpenNiOptions& options) {
  return std::make_unique<OpenNi2Source>(options);
}
}  // namespace

#else  // built without OpenNI2

bool HaveOpenNi() { return false; }

namespace {
[[noreturn]] std::unique_ptr<OpenNiSource> MakeOpenNiSource(const OpenNiOptions&) {
  throw Error("camera: this esdslam was built without OpenNI2 (CMake did not find libopenni2-dev). Install it "
              "(tools/install_deps.sh does) and build again, or plug in your own FrameSource (README, \"Using a camera\")");
}
}  // namespace

#endif

std::unique_ptr<OpenNiSource> OpenOpenNiSource(const OpenNiOptions& options) {
  options.Check();
  if (IsRecording(options.uri) && !std::filesystem::is_regular_file(options.uri))
    throw InputError(options.uri, 0, "no such OpenNI2 recording");
  return MakeOpenNiSource(options);
}

}  // namespace esdslam
