#pragma once
// A table of settings keys bound to fields of options structs. One table describes one file:
// keys are ORB-SLAM2-style flat names ("Camera.fx"); nested YAML maps are flattened with dots.
//
// How a stage adds its keys: write, next to its options struct, a function
//     void BindDynamicSettings(DynamicOptions& options, SettingsTable& table) {
//       table.Add("Dynamic.regionGrowDepthTolerance", &options.depth_tolerance_m);
//       ...
//     }
// and let whoever loads the file (the system stage) build one table from all binders:
//     SettingsTable table; BindCoreSettings(run.core, table); BindDynamicSettings(run.dynamic, table);
//     table.Load(path);
// Keys not in the table produce a warning, so every stage reading the same file must bind into
// the same table. Prefixes given to Ignore() (e.g. "Viewer.") are accepted silently.

#include <functional>
#include <string>
#include <vector>

namespace esdslam {

class SettingsTable {
 public:
  enum class Need { kOptional, kRequired };

  // The field keeps its current value when the key is absent (its default).
  void Add(const std::string& key, double* field, Need need = Need::kOptional);
  void Add(const std::string& key, int* field, Need need = Need::kOptional);  // accepts 640 and 640.0
  void Add(const std::string& key, bool* field, Need need = Need::kOptional); // true/false/1/0
  // A YAML list of scalars ([a, b]) also binds to a string field, as comma-joined text "a,b".
  void Add(const std::string& key, std::string* field, Need need = Need::kOptional);
  void Ignore(const std::string& key_prefix);

  // Reads `path` into the bound fields. Returns the warnings (also logged). Throws InputError.
  std::vector<std::string> Load(const std::string& path) const;
  // Same, from text; `name` is used in messages.
  std::vector<std::string> LoadFromString(const std::string& text, const std::string& name) const;
  // The bound fields as '%YAML:1.0' + 'key: value' lines in table order (doubles round-trip).
  std::string ToYaml() const;
  void Save(const std::string& path) const;

  struct Entry {
    std::string key;
    Need need = Need::kOptional;
    std::string type_name;  // "real", "integer", "boolean", "string" (for messages)
    // Parses the scalar text into the field; returns false if the text has the wrong type.
    std::function<bool(const std::string&)> parse;
    std::function<std::string()> format;
  };
  const std::vector<Entry>& entries() const { return entries_; }

 private:
  void AddEntry(Entry entry);
  std::vector<Entry> entries_;
  std::vector<std::string> ignored_prefixes_;
};

}  // namespace esdslam
