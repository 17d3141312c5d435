// Every numeric settings key is checked against a plausible range, and the error names the key
// and the line it was given on (issue 14 item 2).
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "common/error.h"
#include "system/run_config.h"
#include "system/run_settings.h"
#include "support/temp_path.h"

namespace esdslam {
namespace {

const char* kCore = "%YAML:1.0\nCamera.fx: 500\nCamera.fy: 501\nCamera.cx: 320\nCamera.cy: 240\n";

std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path = testing::TestTempPath("settings_ranges_" + name, ".yaml");
  std::ofstream(path) << text;
  return path;
}

// Loads kCore + "# filler" + `key: value`, expects an InputError at that line naming the key.
void ExpectRejectedAtItsLine(const std::string& key, const std::string& value) {
  // A comment line in between: the line is the key's, not the file's last.
  const std::string text = std::string(kCore) + "# filler\n" + key + ": " + value + "\n# after\n";
  const int line = 7;
  std::string name = key + "_" + value;
  for (char& c : name) {
    if (c == '.' || c == '-' || c == '+') c = '_';
  }
  try {
    LoadRunSettings(WriteTemp(name, text));
    ADD_FAILURE() << key << ": " << value << " was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << key << ": " << value << " -> " << e.what();
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

TEST(SettingsRangesTest, TheIssuesValuesAreRejectedAtTheirLine) {
  ExpectRejectedAtItsLine("Dense.voxelSize", "1e-6");          // hung AnchoredVoxelMap::NearPointOnRay
  ExpectRejectedAtItsLine("Dynamic.maskDilation", "100000");   // asked for a 40 GB allocation
  ExpectRejectedAtItsLine("DepthMapFactor", "1e-9");           // ATE 15 km
  ExpectRejectedAtItsLine("Camera.width", "0");
  ExpectRejectedAtItsLine("ORBextractor.nLevels", "100");
  ExpectRejectedAtItsLine("Dynamic.check.grow.growthBand", "100000");
  ExpectRejectedAtItsLine("Semantic.inputWidth", "100");  // not a multiple of 32
}

// The numeric keys of the table, as SaveRunSettings writes them (booleans and strings skipped).
std::vector<std::string> NumericKeys() {
  std::vector<std::string> keys;
  std::istringstream lines(RunSettingsYaml(RunSettings{}));
  std::string line;
  while (std::getline(lines, line)) {
    const auto colon = line.find(": ");
    if (line.rfind("%YAML", 0) == 0 || colon == std::string::npos) continue;
    const std::string value = line.substr(colon + 2);
    char* end = nullptr;
    std::strtod(value.c_str(), &end);
    if (!value.empty() && *end == '\0') keys.push_back(line.substr(0, colon));
  }
  return keys;
}

TEST(SettingsRangesTest, EveryNumericKeyHasAnUpperAndALowerBound) {
  const std::vector<std::string> keys = NumericKeys();
  EXPECT_GT(keys.size(), 80u);  // core, Dynamic.*, Dense.*, Loop.*, Semantic.*
  for (const std::string& key : keys) {
    ExpectRejectedAtItsLine(key, "1e9");
    ExpectRejectedAtItsLine(key, "-1e9");
  }
}

TEST(SettingsRangesTest, TheShippedDefaultsAreInRange) {
  EXPECT_NO_THROW(LoadRunSettings(WriteTemp("core", kCore)));
}

TEST(SettingsRangesTest, AFlagValueOutOfRangeNamesTheKeyWithoutALine) {
  RunSettings settings = LoadRunSettings(WriteTemp("flag", kCore));
  settings.dense.voxel_size = 1e-6;
  try {
    ResolveRunConfig(settings, RunFlags{});
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("Dense.voxelSize"), std::string::npos) << e.what();
  }
}

TEST(SettingsRangesTest, SeedReachesBothRansacs) {
  RunFlags flags;
  flags.seed = 1234;
  const RunConfig config = ResolveRunConfig(LoadRunSettings(WriteTemp("seed", kCore)), flags);
  EXPECT_EQ(config.slam.loop.relocalizer.pnp.seed, 1234u);
  EXPECT_EQ(config.slam.loop.closer.verification.ransac.seed, 1234u);
  // The default is the options' own seed, so runs without --seed are unchanged.
  const RunConfig plain = ResolveRunConfig(LoadRunSettings(WriteTemp("seed_default", kCore)), RunFlags{});
  EXPECT_EQ(plain.slam.loop.relocalizer.pnp.seed, PnpRansacOptions{}.seed);
  EXPECT_EQ(plain.slam.loop.closer.verification.ransac.seed, RigidRansacOptions{}.seed);
}

}  // namespace
}  // namespace esdslam
