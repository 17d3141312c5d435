#pragma once
// From what a depth camera reports to the run's settings (io/settings.h). A device reports its
// streams' resolution, frame rate and fields of view, not a calibration: the pinhole model they
// imply is fx = (width / 2) / tan(hfov / 2), cx = width / 2 (fy, cy likewise), no distortion.
// Which camera model the run uses is the user's choice:
//   kDevice    the device's model replaces Camera.fx/fy/cx/cy/k*/width/height/fps; Camera.bf
//              keeps its baseline (bf / fx) at the new fx. settings_used.yaml then records it.
//   kSettings  the settings file's calibration (better, when the camera was calibrated) is kept;
//              its image size and frame rate must be the device's.
// Depth from a device is converted to metres by the source itself: DepthMapFactor is not used.

#include <string>

#include "camera/pinhole_camera.h"
#include "io/settings.h"

namespace esdslam {

struct DeviceStreamInfo {
  int width = 0, height = 0;     // pixels
  double fps = 0;                // frames per second
  double horizontal_fov_rad = 0;  // full field of view across the width
  double vertical_fov_rad = 0;
  void Check(const char* stream) const;  // throws Error naming the stream and the value
};

// What the source knows about the device once it is open.
struct DeviceCameraInfo {
  std::string uri;         // the device's (or recording's) URI
  DeviceStreamInfo colour;
  DeviceStreamInfo depth;
  bool hardware_registration = false;  // the device registers depth to colour itself
  bool recording = false;              // a file (.oni), not a live device
};

enum class CameraModelFrom { kDevice, kSettings };
CameraModelFrom ParseCameraModelFrom(const std::string& text);  // "device" | "settings"; throws Error

// The pinhole model a stream's resolution and fields of view imply. Throws Error on bad values.
CameraIntrinsics IntrinsicsFromFieldOfView(const DeviceStreamInfo& stream);

// The settings the run uses with this device (see above). Throws Error when `from` is kSettings
// and the settings' size or frame rate differ from the colour stream's.
Settings SettingsForDevice(Settings settings, const DeviceCameraInfo& device, CameraModelFrom from);

}  // namespace esdslam
