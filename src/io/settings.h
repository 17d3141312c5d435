#pragma once
// Run settings from a YAML file using ORB-SLAM2's keys (flat dotted keys such as Camera.fx;
// OpenCV FileStorage's dialect is accepted, see io/settings_table.h for how the key table
// works and how a later stage adds its own keys).
// ORB-SLAM3's RGB-D format (File.version: "1.0") is read as well: Camera1.fx/fy/cx/cy/k1/k2/p1/
// p2/k3 for Camera.*, Stereo.ThDepth for ThDepth, RGBD.DepthMapFactor for DepthMapFactor and
// Stereo.b (baseline, m) for Camera.bf = Stereo.b * fx; Camera.type must be PinHole. Files
// are saved in ORB-SLAM2's keys.

#include <map>
#include <string>
#include <vector>

#include "camera/pinhole_camera.h"
#include "feature/orb_options.h"

namespace esdslam {

class SettingsTable;

struct Settings {
  CameraIntrinsics camera;        // Camera.fx/fy/cx/cy (required), k1 k2 p1 p2 k3, width, height
  double fps = 30;                // Camera.fps
  double depth_map_factor = 5000; // DepthMapFactor: depth PNG value per metre
  double th_depth = 40;           // ThDepth: close/far point threshold, in multiples of the baseline
  double bf = 40;                 // Camera.bf = baseline (m) * fx (px)
  // Camera.readoutTime: seconds from the first to the last image row of a rolling-shutter colour
  // camera (0 = global shutter, no correction). Not an ORB-SLAM2 key.
  double readout_time_s = 0;
  int rgb_order = 1;              // Camera.RGB: 1 = images are RGB, 0 = BGR
  OrbOptions orb;                 // ORBextractor.*
  // ORB-SLAM3 keys read on input only (not saved): File.version ("" or "1.0"), Camera.type
  // ("PinHole") and Stereo.b (baseline in m; 0 = not given, else bf = stereo_b * fx on load).
  std::string file_version;
  std::string camera_type = "PinHole";
  double stereo_b = 0;

  // Throws SettingError naming the key for any value outside its plausible range.
  void Check() const;
};

// Binds every key of `settings` into `table` (the single key table of the core settings).
void BindCoreSettings(Settings& settings, SettingsTable& table);

// After loading: Stereo.b into bf (an error when Camera.bf is given too). Throws SettingError.
void ResolveOrbSlam3Keys(Settings& settings, const std::map<std::string, int>& key_lines);

// Loads and checks. Unknown keys are warned about (file and line) and, if `warnings` is given,
// appended to it. Throws InputError for a missing file, YAML syntax errors, a missing required
// key (names file and key), a wrong type (file and line) and failed checks.
Settings LoadSettings(const std::string& path, std::vector<std::string>* warnings = nullptr);

// Writes the effective settings in the same key format (loadable by LoadSettings and ORB-SLAM2).
void SaveSettings(const Settings& settings, const std::string& path);

}  // namespace esdslam
