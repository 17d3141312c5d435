#include "io/settings.h"

#include "common/error.h"
#include "common/setting_error.h"
#include "io/settings_table.h"

namespace esdslam {

void Settings::Check() const {
  camera.Check();
  CheckRange("Camera.fps", fps, 0.1, 1000.0, "Hz");
  // PNG value per metre: 1 (metres) .. 100000 (10 um steps); TUM 5000, Kinect mm 1000.
  CheckRange("DepthMapFactor", depth_map_factor, 1.0, 1e5);
  CheckRange("ThDepth", th_depth, 1.0, 1000.0, "baselines");
  CheckRange("Camera.bf", bf, 0.1, 1e5, "m*px");
  // At most a frame period of a 10 Hz camera; a readout longer than the frame period is impossible.
  CheckRange("Camera.readoutTime", readout_time_s, 0.0, 0.1, "s");
  CheckSetting(readout_time_s <= 1.0 / fps, "Camera.readoutTime", "must not exceed the frame period 1 / Camera.fps");
  CheckSetting(rgb_order == 0 || rgb_order == 1, "Camera.RGB", "must be 0 (BGR) or 1 (RGB)");
  CheckSetting(file_version.empty() || file_version == "1.0", "File.version",
               "only ORB-SLAM3's \"1.0\" format is known, got \"" + file_version + "\"");
  CheckSetting(camera_type == "PinHole", "Camera.type",
               "only \"PinHole\" cameras are supported, got \"" + camera_type + "\"");
  CheckRange("Stereo.b", stereo_b, 0.0, 10.0, "m");
  orb.Check();
}

void ResolveOrbSlam3Keys(Settings& settings, const std::map<std::string, int>& key_lines) {
  if (key_lines.count("Stereo.b") == 0) return;
  CheckSetting(key_lines.count("Camera.bf") == 0, "Stereo.b", "give Stereo.b (ORB-SLAM3) or Camera.bf, not both");
  CheckRange("Stereo.b", settings.stereo_b, 1e-3, 10.0, "m");
  settings.bf = settings.stereo_b * settings.camera.fx;
}

// The single table of core keys (ORB-SLAM2 names). Later stages bind their own keys in their
// own Bind*Settings function (see io/settings_table.h).
void BindCoreSettings(Settings& settings, SettingsTable& table) {
  using Need = SettingsTable::Need;
  CameraIntrinsics& camera = settings.camera;
  table.Add("Camera.fx", &camera.fx, Need::kRequired);
  table.Add("Camera.fy", &camera.fy, Need::kRequired);
  table.Add("Camera.cx", &camera.cx, Need::kRequired);
  table.Add("Camera.cy", &camera.cy, Need::kRequired);
  table.Add("Camera.k1", &camera.k1);
  table.Add("Camera.k2", &camera.k2);
  table.Add("Camera.p1", &camera.p1);
  table.Add("Camera.p2", &camera.p2);
  table.Add("Camera.k3", &camera.k3);
  table.Add("Camera.width", &camera.width);
  table.Add("Camera.height", &camera.height);
  table.Add("Camera.fps", &settings.fps);
  table.Add("Camera.bf", &settings.bf);
  table.Add("Camera.readoutTime", &settings.readout_time_s);
  table.Add("Camera.RGB", &settings.rgb_order);
  table.Add("ThDepth", &settings.th_depth);
  table.Add("DepthMapFactor", &settings.depth_map_factor);
  table.Add("ORBextractor.nFeatures", &settings.orb.num_features);
  table.Add("ORBextractor.scaleFactor", &settings.orb.scale_factor);
  table.Add("ORBextractor.nLevels", &settings.orb.num_levels);
  table.Add("ORBextractor.iniThFAST", &settings.orb.initial_fast_threshold);
  table.Add("ORBextractor.minThFAST", &settings.orb.min_fast_threshold);
  // ORB-SLAM3's RGB-D format (read only; saved files use the keys above).
  table.Add("File.version", &settings.file_version);
  table.Add("Camera.type", &settings.camera_type);
  table.Add("Stereo.b", &settings.stereo_b);
  for (const char* key : {"File.version", "Camera.type", "Stereo.b"}) table.InputOnly(key);
  for (const char* name : {"fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3"})
    table.Alias(std::string("Camera1.") + name, std::string("Camera.") + name);
  table.Alias("Stereo.ThDepth", "ThDepth");
  table.Alias("RGBD.DepthMapFactor", "DepthMapFactor");
  table.Ignore("Viewer.");  // ORB-SLAM2/3's Pangolin viewer settings
}

Settings LoadSettings(const std::string& path, std::vector<std::string>* warnings) {
  Settings settings;
  SettingsTable table;
  BindCoreSettings(settings, table);
  SettingsTable::KeyLines lines;
  std::vector<std::string> load_warnings = table.Load(path, &lines);
  CheckWithKeyLines(path, lines, [&] {
    ResolveOrbSlam3Keys(settings, lines);
    settings.Check();
  });
  if (warnings) warnings->insert(warnings->end(), load_warnings.begin(), load_warnings.end());
  return settings;
}

void SaveSettings(const Settings& settings, const std::string& path) {
  Settings copy = settings;
  SettingsTable table;
  BindCoreSettings(copy, table);
  table.Save(path);
}

}  // namespace esdslam
