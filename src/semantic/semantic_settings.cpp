#include "semantic/semantic_settings.h"

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include "common/error.h"

namespace esdslam {
namespace fs = std::filesystem;
namespace {

YAML::Node ParseYamlSkippingDirective(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open settings file");
  std::stringstream text;
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    // Keep line numbers: blank out the OpenCV directive instead of dropping the line.
    text << ((first && line.rfind("%YAML", 0) == 0) ? "" : line) << '\n';
    first = false;
  }
  try {
    return YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    throw InputError(path, e.mark.line + 1, fmt::format("YAML syntax error: {}", e.msg));
  }
}

template <typename T>
void Read(const YAML::Node& root, const std::string& path, const std::string& key, T& value) {
  const YAML::Node node = root[key];
  if (!node) return;
  try {
    value = node.as<T>();
  } catch (const YAML::Exception&) {
    throw InputError(path, node.Mark().line + 1, fmt::format("{}: unexpected value type", key));
  }
}

std::vector<std::string> SplitNames(const std::string& text) {
  std::vector<std::string> names;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto b = item.find_first_not_of(" \t");
    const auto e = item.find_last_not_of(" \t");
    if (b != std::string::npos) names.push_back(item.substr(b, e - b + 1));
  }
  return names;
}

void ReadNames(const YAML::Node& root, const std::string& path, const std::string& key, std::vector<std::string>& names) {
  const YAML::Node node = root[key];
  if (!node) return;
  if (node.IsSequence()) {
    names.clear();
    for (const auto& item : node) names.push_back(item.as<std::string>());
  } else if (node.IsScalar()) {
    names = SplitNames(node.as<std::string>());
  } else {
    throw InputError(path, node.Mark().line + 1, fmt::format("{}: expected a list of class names", key));
  }
}

bool ReadFlag(const YAML::Node& root, const std::string& path, const std::string& key, bool fallback) {
  int value = fallback ? 1 : 0;  // ORB-SLAM2 files write flags as 0/1
  Read(root, path, key, value);
  return value != 0;
}

// Input size from a file name ending in _<W>x<H>.onnx.
bool SizeFromModelName(const std::string& model, int& width, int& height) {
  static const std::regex pattern(R"(_(\d+)x(\d+)\.onnx$)");
  std::smatch m;
  if (!std::regex_search(model, m, pattern)) return false;
  width = std::stoi(m[1]);
  height = std::stoi(m[2]);
  return true;
}

std::string ExecutableDir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

}  // namespace

std::string ResolveModelPath(const std::string& path, const std::string& settings_dir) {
  if (path.empty() || fs::path(path).is_absolute() || fs::exists(path)) return path;
  std::vector<fs::path> roots;
  if (!settings_dir.empty()) roots.emplace_back(settings_dir);
  const std::string exe_dir = ExecutableDir();
  if (!exe_dir.empty()) {
    roots.emplace_back(exe_dir);
    roots.emplace_back(fs::path(exe_dir) / "..");
    roots.emplace_back(fs::path(exe_dir) / ".." / "..");
  }
  for (const auto& root : roots) {
    const fs::path candidate = root / path;
    if (fs::exists(candidate)) return fs::weakly_canonical(candidate).string();
  }
  return path;
}

void SetModel(SemanticSettings& settings, const std::string& path, const std::string& settings_dir) {
  settings.onnx.model_path = ResolveModelPath(path, settings_dir);
  SizeFromModelName(path, settings.onnx.input_width, settings.onnx.input_height);
}

SemanticSettings LoadSemanticSettings(const std::string& path) {
  SemanticSettings s;
  std::string model = kDefaultSegmentationModel;
  std::string settings_dir;
  YAML::Node root;
  if (!path.empty()) {
    root = ParseYamlSkippingDirective(path);
    settings_dir = fs::path(path).parent_path().string();
  }
  std::string kind = "onnx";
  Read(root, path, "Semantic.segmenter", kind);
  if (kind == "folder") {
    s.kind = SemanticSettings::Kind::kFolder;
  } else if (kind != "onnx") {
    throw InputError(path, root["Semantic.segmenter"].Mark().line + 1, "Semantic.segmenter must be onnx or folder");
  }
  Read(root, path, "Semantic.model", model);
  SetModel(s, model, settings_dir);
  Read(root, path, "Semantic.inputWidth", s.onnx.input_width);
  Read(root, path, "Semantic.inputHeight", s.onnx.input_height);
  Read(root, path, "Semantic.threads", s.onnx.threads);
  s.onnx.upsample_scores = ReadFlag(root, path, "Semantic.upsampleScores", s.onnx.upsample_scores);
  ReadNames(root, path, "Semantic.dynamicClasses", s.groups.dynamic_classes);
  ReadNames(root, path, "Semantic.potentiallyDynamicClasses", s.groups.potentially_dynamic_classes);
  Read(root, path, "Semantic.maskFolder", s.folder.folder);
  Read(root, path, "Semantic.maskTolerance", s.folder.tolerance_s);
  s.folder.allow_missing = ReadFlag(root, path, "Semantic.allowMissingMasks", s.folder.allow_missing);
  if (ReadFlag(root, path, "Semantic.realtime", false)) s.mode = SegmentationMode::kNewestWins;
  try {
    s.groups.Check(s.onnx.class_names);
    if (s.kind == SemanticSettings::Kind::kOnnx) s.onnx.Check();
    else s.folder.Check();
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    throw InputError(path.empty() ? "<default semantic settings>" : path, 0, e.what());
  }
  return s;
}

std::unique_ptr<Segmenter> MakeSegmenter(const SemanticSettings& settings) {
  if (settings.kind == SemanticSettings::Kind::kFolder) return std::make_unique<FolderSegmenter>(settings.folder);
  return std::make_unique<OnnxSegmenter>(settings.onnx);
}

}  // namespace esdslam
