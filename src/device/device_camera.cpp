#include "device/device_camera.h"

#include <cmath>

#include <fmt/format.h>

#include "common/error.h"

namespace esdslam {

void DeviceStreamInfo::Check(const char* stream) const {
  constexpr double kPi = 3.14159265358979323846;
  if (width <= 0 || height <= 0) throw Error(fmt::format("camera: {} stream size {}x{} is empty", stream, width, height));
  if (!(fps > 0)) throw Error(fmt::format("camera: {} stream frame rate {} must be > 0", stream, fps));
  for (const double fov : {horizontal_fov_rad, vertical_fov_rad})
    if (!(fov > 0 && fov < kPi))
      throw Error(fmt::format("camera: {} stream field of view {} rad must be in (0, pi)", stream, fov));
}

CameraModelFrom ParseCameraModelFrom(const std::string& text) {
  if (text == "device") return CameraModelFrom::kDevice;
  if (text == "settings") return CameraModelFrom::kSettings;
  throw Error("camera model must come from 'device' or 'settings', got '" + text + "'");
}

CameraIntrinsics IntrinsicsFromFieldOfView(const DeviceStreamInfo& stream) {
  stream.Check("colour");
  CameraIntrinsics camera;
  camera.width = stream.width;
  camera.height = stream.height;
  camera.fx = 0.5 * stream.width / std::tan(0.5 * stream.horizontal_fov_rad);
  camera.fy = 0.5 * stream.height / std::tan(0.5 * stream.vertical_fov_rad);
  camera.cx = 0.5 * stream.width;
  camera.cy = 0.5 * stream.height;
  return camera;
}

Settings SettingsForDevice(Settings settings, const DeviceCameraInfo& device, CameraModelFrom from) {
  const DeviceStreamInfo& colour = device.colour;
  colour.Check("colour");
  if (from == CameraModelFrom::kSettings) {
    const CameraIntrinsics& c = settings.camera;
    if (c.width != colour.width || c.height != colour.height)
      throw Error(fmt::format("camera {}: the settings describe {}x{} images, the device delivers {}x{} (use the "
                              "device's camera model, or settings for this resolution)",
                              device.uri, c.width, c.height, colour.width, colour.height));
    if (std::abs(settings.fps - colour.fps) > 0.5)
      throw Error(fmt::format("camera {}: the settings say Camera.fps {}, the device delivers {} fps", device.uri,
                              settings.fps, colour.fps));
    return settings;
  }
  const double baseline_m = settings.bf / settings.camera.fx;  // kept: a property of the rig
  settings.camera = IntrinsicsFromFieldOfView(colour);
  settings.bf = baseline_m * settings.camera.fx;
  settings.fps = colour.fps;
  settings.Check();
  return settings;
}

}  // namespace esdslam
