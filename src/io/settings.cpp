#include "io/settings.h"

#include "common/error.h"
#include "io/settings_table.h"

namespace esdslam {

void Settings::Check() const {
  camera.Check();
  if (!(fps > 0)) throw Error("Camera.fps must be > 0");
  if (!(depth_map_factor > 0)) throw Error("DepthMapFactor must be > 0");
  if (!(th_depth > 0)) throw Error("ThDepth must be > 0");
  if (!(bf > 0)) throw Error("Camera.bf must be > 0");
  if (rgb_order != 0 && rgb_order != 1) throw Error("Camera.RGB must be 0 (BGR) or 1 (RGB)");
  orb.Check();
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
  table.Add("Camera.RGB", &settings.rgb_order);
  table.Add("ThDepth", &settings.th_depth);
  table.Add("DepthMapFactor", &settings.depth_map_factor);
  table.Add("ORBextractor.nFeatures", &settings.orb.num_features);
  table.Add("ORBextractor.scaleFactor", &settings.orb.scale_factor);
  table.Add("ORBextractor.nLevels", &settings.orb.num_levels);
  table.Add("ORBextractor.iniThFAST", &settings.orb.initial_fast_threshold);
  table.Add("ORBextractor.minThFAST", &settings.orb.min_fast_threshold);
  table.Ignore("Viewer.");  // ORB-SLAM2's Pangolin viewer settings
}

Settings LoadSettings(const std::string& path, std::vector<std::string>* warnings) {
  Settings settings;
  SettingsTable table;
  BindCoreSettings(settings, table);
  std::vector<std::string> load_warnings = table.Load(path);
  try {
    settings.Check();
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    throw InputError(path, 0, e.what());
  }
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
