// Test data only (no tests): see dynamic_sequence.h.
#include <filesystem>
#include <fstream>
#include <map>

#include "synth/sequence_writer.h"
#include "system/dynamic_sequence.h"
#include "support/temp_path.h"

namespace esdslam::testing {

const std::string& DynamicTestSequence(int frames) {
  static std::map<int, std::string> dirs;
  auto it = dirs.find(frames);
  if (it != dirs.end()) return it->second;
  SynthOptions options = SynthPreset("dynamic");
  options.num_frames = frames;
  options.supersampling = 1;
  const SyntheticScene scene(options);
  const std::string out =
      TestTempPath("dynamic_run_test_" + std::to_string(frames));
  std::filesystem::remove_all(out);
  WriteSynthSequence(scene, out);
  std::ofstream(out + "/run.yaml") << SynthSettingsYaml(options) << "\nSemantic.segmenter: folder\n"
                                   << "Semantic.maskFolder: " << out << "/labels\n"
                                   << "Dynamic.maskDilation: 0\n";  // measure the refined mask itself
  return dirs.emplace(frames, out).first->second;
}

const std::string& OcclusionTestSequence() {
  static const std::string dir = [] {
    SynthOptions options = SynthPreset("occlusion");
    options.supersampling = 1;  // 4x faster rendering; the tracking problem is the same
    const SyntheticScene scene(options);
    const std::string out = TestTempPath("occlusion_sequence");
    std::filesystem::remove_all(out);
    WriteSynthSequence(scene, out);
    std::ofstream(out + "/run.yaml") << SynthSettingsYaml(options) << "\nSemantic.segmenter: folder\n"
                                     << "Semantic.maskFolder: " << out << "/labels\n";
    return out;
  }();
  return dir;
}

const std::string& RollingTestSequence() {
  static const std::string dir = [] {
    const SyntheticScene scene(SynthPreset("rolling"));
    const std::string out = TestTempPath("rolling_sequence");
    std::filesystem::remove_all(out);
    WriteSynthSequence(scene, out);
    return out;
  }();
  return dir;
}

}  // namespace esdslam::testing
