// Fuzz target: the settings reader (io/settings_table.h: OpenCV/ORB-SLAM2/3 YAML dialect,
// flattening, aliases, scalar parsing, lists) with the core keys and their range checks
// (io/settings.h), plus one key of every type. The other stages' range checks are plain
// comparisons, covered key by key by tests/system/settings_ranges_test.cpp; linking them would
// build the whole library in the fuzz build.
#include "common/error.h"
#include "fuzz/fuzz_input.h"
#include "io/settings.h"
#include "io/settings_table.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = esdslam::fuzz::WriteScratch("settings.yaml", data, size);
  try {
    esdslam::LoadSettings(path);
  } catch (const esdslam::Error&) {
  }
  esdslam::Settings settings;
  std::string text;
  bool flag = false;
  esdslam::SettingsTable table;
  esdslam::BindCoreSettings(settings, table);
  table.Add("Extra.text", &text);
  table.Add("Extra.flag", &flag);
  table.MakeAllOptional();
  try {
    esdslam::SettingsTable::KeyLines lines;
    table.Load(path, &lines);
    esdslam::CheckWithKeyLines(path, lines, [&] {
      esdslam::ResolveOrbSlam3Keys(settings, lines);
      settings.Check();
    });
    table.ToYaml();
  } catch (const esdslam::Error&) {
  }
  return 0;
}
