#include "io/settings_table.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include "common/error.h"

namespace esdslam {
namespace {

bool ParseReal(const std::string& text, double* value) {
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const double parsed = std::strtod(text.c_str(), &end);
  if (*end != '\0' || errno == ERANGE || !std::isfinite(parsed)) return false;
  *value = parsed;
  return true;
}

// Integers may be written as integral reals ("640.0"), as OpenCV's FileStorage accepts.
bool ParseInteger(const std::string& text, int* value) {
  double parsed = 0;
  if (!ParseReal(text, &parsed) || parsed != std::floor(parsed) || std::abs(parsed) > 2147483647.0) return false;
  *value = static_cast<int>(parsed);
  return true;
}

bool ParseBool(const std::string& text, bool* value) {
  static const std::map<std::string, bool> kWords = {{"true", true},  {"True", true},   {"TRUE", true},
                                                     {"1", true},     {"false", false}, {"False", false},
                                                     {"FALSE", false}, {"0", false}};
  const auto it = kWords.find(text);
  if (it == kWords.end()) return false;
  *value = it->second;
  return true;
}

std::string QuoteYamlString(const std::string& text) {
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') quoted.push_back('\\');
    quoted.push_back(c);
  }
  return quoted + "\"";
}

// OpenCV writes '%YAML:1.0', which yaml-cpp rejects: blank that line (keeps line numbers).
std::string DropOpenCvHeader(const std::string& text) {
  if (text.rfind("%YAML", 0) != 0) return text;
  const auto end_of_line = text.find('\n');
  return end_of_line == std::string::npos ? std::string() : text.substr(end_of_line);
}

struct FlatValue {
  YAML::Node node;
  int line = 0;  // 1-based line of the key
};

bool IsPlainMap(const YAML::Node& node) {
  const std::string& tag = node.Tag();
  return node.IsMap() && (tag.empty() || tag == "?" || tag == "!");
}

// Nested maps become dotted keys ("Camera: {fx: 1}" == "Camera.fx: 1").
void Flatten(const YAML::Node& map, const std::string& prefix, const std::string& name,
             std::vector<std::pair<std::string, FlatValue>>& out) {
  for (const auto& item : map) {
    const int line = item.first.Mark().line + 1;
    if (!item.first.IsScalar()) throw InputError(name, line, "settings keys must be plain names");
    const std::string key = prefix + item.first.Scalar();
    if (IsPlainMap(item.second)) {
      Flatten(item.second, key + ".", name, out);
    } else {
      out.push_back({key, {item.second, line}});
    }
  }
}

bool IsScalarList(const YAML::Node& list) {
  for (const auto& item : list) {
    if (!item.IsScalar()) return false;
  }
  return true;
}

std::string JoinScalars(const YAML::Node& list) {
  std::string text;
  for (const auto& item : list) text += (text.empty() ? "" : ",") + item.Scalar();
  return text;
}

}  // namespace

void SettingsTable::AddEntry(Entry entry) {
  for (const Entry& existing : entries_) {
    if (existing.key == entry.key) throw Error("settings key bound twice: " + entry.key);
  }
  entries_.push_back(std::move(entry));
}

void SettingsTable::Add(const std::string& key, double* field, Need need) {
  AddEntry({key, need, "real", [field](const std::string& s) { return ParseReal(s, field); },
            [field] { return fmt::format("{}", *field); }});
}

void SettingsTable::Add(const std::string& key, int* field, Need need) {
  AddEntry({key, need, "integer", [field](const std::string& s) { return ParseInteger(s, field); },
            [field] { return fmt::format("{}", *field); }});
}

void SettingsTable::Add(const std::string& key, bool* field, Need need) {
  AddEntry({key, need, "boolean", [field](const std::string& s) { return ParseBool(s, field); },
            [field] { return std::string(*field ? "true" : "false"); }});
}

void SettingsTable::Add(const std::string& key, std::string* field, Need need) {
  AddEntry({key, need, "string",
            [field](const std::string& s) {
              *field = s;
              return true;
            },
            [field] { return QuoteYamlString(*field); }});
}

void SettingsTable::Ignore(const std::string& key_prefix) { ignored_prefixes_.push_back(key_prefix); }

std::vector<std::string> SettingsTable::Load(const std::string& path) const {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path, 0, "settings file not found");
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open settings file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return LoadFromString(buffer.str(), path);
}

std::vector<std::string> SettingsTable::LoadFromString(const std::string& text, const std::string& name) const {
  YAML::Node root;
  try {
    root = YAML::Load(DropOpenCvHeader(text));
  } catch (const YAML::Exception& e) {
    throw InputError(name, e.mark.line + 1, "YAML syntax error: " + e.msg);
  }
  std::vector<std::pair<std::string, FlatValue>> values;
  if (root.IsMap()) {
    Flatten(root, "", name, values);
  } else if (root.IsDefined() && !root.IsNull()) {
    throw InputError(name, root.Mark().line + 1, "settings file must be a map of 'key: value' lines");
  }
  std::map<std::string, int> seen;  // key -> line
  std::vector<std::string> warnings;
  for (const auto& [key, value] : values) {
    if (!seen.emplace(key, value.line).second) {
      throw InputError(name, value.line, fmt::format("duplicate key '{}' (first on line {})", key, seen[key]));
    }
    const Entry* entry = nullptr;
    for (const Entry& candidate : entries_) {
      if (candidate.key == key) entry = &candidate;
    }
    if (entry == nullptr) {
      bool ignored = false;
      for (const std::string& prefix : ignored_prefixes_) ignored = ignored || key.rfind(prefix, 0) == 0;
      if (!ignored) {
        warnings.push_back(fmt::format("{}:{}: unknown settings key '{}' (ignored)", name, value.line, key));
        spdlog::warn("{}", warnings.back());
      }
      continue;
    }
    if (value.node.IsSequence() && entry->type_name == "string" && IsScalarList(value.node)) {
      entry->parse(JoinScalars(value.node));  // a list of scalars binds to text as "a,b,c"
      continue;
    }
    if (!value.node.IsScalar() || !entry->parse(value.node.Scalar())) {
      const std::string got = value.node.IsScalar() ? "'" + value.node.Scalar() + "'"
                              : value.node.IsNull() ? std::string("no value")
                                                    : std::string("a list or map");
      throw InputError(name, value.line, fmt::format("{}: expected {}, got {}", key, entry->type_name, got));
    }
  }
  for (const Entry& entry : entries_) {
    if (entry.need == Need::kRequired && seen.count(entry.key) == 0) {
      throw InputError(name, 0, fmt::format("missing required key '{}'", entry.key));
    }
  }
  return warnings;
}

std::string SettingsTable::ToYaml() const {
  std::string text = "%YAML:1.0\n";
  for (const Entry& entry : entries_) text += entry.key + ": " + entry.format() + "\n";
  return text;
}

void SettingsTable::Save(const std::string& path) const {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ignored;
  if (!parent.empty()) std::filesystem::create_directories(parent, ignored);
  std::ofstream out(path);
  out << ToYaml();
  out.close();
  if (!out) throw Error("cannot write settings file " + path);
}

}  // namespace esdslam
