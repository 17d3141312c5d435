#pragma once
// A live OpenNI2 RGB-D camera (Kinect, Xtion, Orbbec-class sensors) or an OpenNI2 recording
// (.oni) as a FrameSource (io/frame_source.h). Optional build component: built when CMake finds
// libopenni2 (Debian: libopenni2-dev); otherwise OpenOpenNiSource throws an Error saying so.
//
// Per Next(): the colour and depth frames of one moment (the device's depth-colour sync on),
// depth converted from millimetres to metres and registered to the colour camera
// (device/rgbd_conversion.h), colour from RGB888 to BGR. The frame's time is the colour frame's
// device timestamp in seconds. A live camera keeps delivering at its frame rate whether or not
// Next() is called; frames it dropped meanwhile (gaps in its frame numbers) are counted in
// RgbdFrame::dropped_before. A recording is read frame by frame ("manual" playback speed: no
// frame is dropped; wrap it in a LivePlaybackSource to play it on its own clock) and ends
// after its last frame.
//
// Registration (OpenNiOptions::registration):
//   kDevice    the device's hardware depth-to-colour registration; when the device has none,
//              software registration with both streams' field-of-view models and
//              colour_from_depth (device/rgbd_conversion.h)
//   kOff       depth as the device delivers it (already registered recordings)
// Threads: one consumer thread; OpenNI's own threads fill its buffers.

#include <memory>
#include <string>

#include "common/geometry.h"
#include "device/device_camera.h"
#include "io/frame_source.h"

namespace esdslam {

enum class DepthRegistration { kDevice, kOff };
DepthRegistration ParseDepthRegistration(const std::string& text);  // "device" | "off"; throws Error

struct OpenNiOptions {
  std::string uri;                 // "" = the first device attached; a path ending in .oni = a recording
  int width = 640, height = 480;   // requested video mode of both streams (a recording has its own)
  int fps = 30;
  DepthRegistration registration = DepthRegistration::kDevice;
  Rigid3 colour_from_depth;        // software registration only (metres); identity by default
  int frame_timeout_ms = 2000;     // no frame for this long: Error (device unplugged, stream stalled)
  void Check() const;              // throws Error
};

class OpenNiSource : public FrameSource {
 public:
  // What the device reports (resolution, frame rate, fields of view, hardware registration).
  virtual const DeviceCameraInfo& info() const = 0;
};

// Whether this build has the OpenNI2 source.
bool HaveOpenNi();

// Opens the device or recording and starts both streams. Throws Error with what to do when no
// device is attached, the URI names no device, the build has no OpenNI2, or a stream cannot
// start; InputError naming the file when a recording does not exist.
std::unique_ptr<OpenNiSource> OpenOpenNiSource(const OpenNiOptions& options);

}  // namespace esdslam
