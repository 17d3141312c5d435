#include "io/settings_table.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include "common/error.h"
#include "common/setting_error.h"

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

const SettingsTable::Entry* FindEntry(const std::vector<SettingsTable::Entry>& entries, const std::string& key) {
  for (const SettingsTable::Entry& candidate : entries) {
    if (candidate.key == key) return &candidate;
  }
  return nullptr;
}

std::string CanonicalKey(const SettingsTable::Entry& entry) {
  return entry.canonical.empty() ? entry.key : entry.canonical;
}

}  // namespace

std::string NormalizeOpenCvYaml(const std::string& text) {
  // A plain key at the start of a line (after indentation), a colon, then a value character.
  static const std::regex kNoSpace(R"(^(\s*[A-Za-z_][A-Za-z0-9_.\-]*):([^\s:/\\]))");
  std::string out;
  out.reserve(text.size() + 16);
  std::size_t begin = 0;
  bool first = true;
  while (begin <= text.size()) {
    const std::size_t end = std::min(text.find('\n', begin), text.size());
    std::string line = text.substr(begin, end - begin);
    if (first && line.rfind("%YAML", 0) == 0) line.clear();  // OpenCV's header; yaml-cpp rejects it
    out += std::regex_replace(line, kNoSpace, "$1: $2", std::regex_constants::format_first_only);
    if (end == text.size()) break;
    out += '\n';
    begin = end + 1;
    first = false;
  }
  return out;
}

void CheckWithKeyLines(const std::string& name, const SettingsTable::KeyLines& lines,
                       const std::function<void()>& check) {
  try {
    check();
  } catch (const InputError&) {
    throw;
  } catch (const SettingError& e) {
    const auto it = lines.find(e.key());
    throw InputError(name, it == lines.end() ? 0 : it->second, e.what());
  } catch (const Error& e) {
    throw InputError(name, 0, e.what());
  }
}

void SettingsTable::AddEntry(Entry entry) {
  for (const Entry& existing : entries_) {
    if (existing.key == entry.key) throw Error("settings key bound twice: " + entry.key);
  }
  entries_.push_back(std::move(entry));
}

void SettingsTable::Add(const std::string& key, double* field, Need need) {
  AddEntry({key, need, "real", [field](const std::string& s) { return ParseReal(s, field); },
            [field] { return fmt::format("{}", *field); }, /*canonical=*/""});
}

void SettingsTable::Add(const std::string& key, int* field, Need need) {
  AddEntry({key, need, "integer", [field](const std::string& s) { return ParseInteger(s, field); },
            [field] { return fmt::format("{}", *field); }, /*canonical=*/""});
}

void SettingsTable::Add(const std::string& key, bool* field, Need need) {
  AddEntry({key, need, "boolean", [field](const std::string& s) { return ParseBool(s, field); },
            [field] { return std::string(*field ? "true" : "false"); }, /*canonical=*/""});
}

void SettingsTable::Add(const std::string& key, std::string* field, Need need) {
  AddEntry({key, need, "string",
            [field](const std::string& s) {
              *field = s;
              return true;
            },
            [field] { return QuoteYamlString(*field); }, /*canonical=*/""});
}

void SettingsTable::InputOnly(const std::string& key) {
  for (Entry& entry : entries_) {
    if (entry.key == key) entry.saved = false;
  }
}

void SettingsTable::Alias(const std::string& alias, const std::string& key) {
  const Entry* target = FindEntry(entries_, key);
  if (target == nullptr) throw Error("settings alias " + alias + " of an unbound key " + key);
  Entry entry = *target;
  entry.key = alias;
  entry.canonical = key;
  entry.need = Need::kOptional;
  entry.saved = false;
  AddEntry(std::move(entry));
}

void SettingsTable::MakeAllOptional() {
  for (Entry& entry : entries_) entry.need = Need::kOptional;
}

void SettingsTable::Ignore(const std::string& key_prefix) { ignored_prefixes_.push_back(key_prefix); }

std::vector<std::string> SettingsTable::Load(const std::string& path, KeyLines* lines) const {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path, 0, "settings file not found");
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open settings file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return LoadFromString(buffer.str(), path, lines);
}

std::vector<std::string> SettingsTable::LoadFromString(const std::string& text, const std::string& name,
                                                       KeyLines* lines) const {
  YAML::Node root;
  try {
    root = YAML::Load(NormalizeOpenCvYaml(text));
  } catch (const YAML::Exception& e) {
    throw InputError(name, e.mark.line + 1, "YAML syntax error: " + e.msg);
  }
  std::vector<std::pair<std::string, FlatValue>> values;
  if (root.IsMap()) {
    Flatten(root, "", name, values);
  } else if (root.IsDefined() && !root.IsNull()) {
    throw InputError(name, root.Mark().line + 1, "settings file must be a map of 'key: value' lines");
  }
  KeyLines seen;                                       // key -> line
  std::map<std::string, std::pair<std::string, int>> given;  // canonical key -> key as given, line
  std::vector<std::string> warnings;
  for (const auto& [key, value] : values) {
    if (!seen.emplace(key, value.line).second) {
      throw InputError(name, value.line, fmt::format("duplicate key '{}' (first on line {})", key, seen[key]));
    }
    const Entry* entry = FindEntry(entries_, key);
    if (entry != nullptr && !given.emplace(CanonicalKey(*entry), std::make_pair(key, value.line)).second) {
      const auto& first = given[CanonicalKey(*entry)];
      throw InputError(name, value.line,
                       fmt::format("'{}' gives the same setting as '{}' on line {}", key, first.first, first.second));
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
    if (entry.need == Need::kRequired && given.count(entry.key) == 0) {
      throw InputError(name, 0, fmt::format("missing required key '{}'", entry.key));
    }
  }
  // A check names the canonical key: map it to the line of whichever form was given.
  for (const auto& [canonical, key_line] : given) seen.emplace(canonical, key_line.second);
  if (lines != nullptr) *lines = std::move(seen);
  return warnings;
}

std::string SettingsTable::ToYaml() const {
  std::string text = "%YAML:1.0\n";
  for (const Entry& entry : entries_) {
    if (entry.saved) text += entry.key + ": " + entry.format() + "\n";
  }
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
