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
//
// The dialect is OpenCV FileStorage's YAML, in which ORB-SLAM2/3 files are written: a leading
// '%YAML:1.0' line, and 'key:value' without a space after the colon (ORB-SLAM2's
// 'Viewer.PointSize:2'). Both are accepted; reported line numbers are those of the file.
// Alias() names a second key for the same field (ORB-SLAM3's 'Camera1.fx' for 'Camera.fx');
// giving both is an error. Range checks belong to the options' Check() (common/error.h
// CheckRange); CheckWithKeyLines turns their SettingError into an error at the key's line.

#include <functional>
#include <map>
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
  // Marks the added `key` as read but never written by ToYaml (an input-only form: Stereo.b).
  void InputOnly(const std::string& key);
  // `alias` reads into the field of the already added `key`; not written by ToYaml.
  void Alias(const std::string& alias, const std::string& key);
  void Ignore(const std::string& key_prefix);
  // Makes every key optional (a file read for one part only, e.g. Semantic.* by `esdslam segment`).
  void MakeAllOptional();

  using KeyLines = std::map<std::string, int>;  // key as given in the file -> its 1-based line

  // Reads `path` into the bound fields. Returns the warnings (also logged); fills `lines` when
  // given. Throws InputError.
  std::vector<std::string> Load(const std::string& path, KeyLines* lines = nullptr) const;
  // Same, from text; `name` is used in messages.
  std::vector<std::string> LoadFromString(const std::string& text, const std::string& name,
                                          KeyLines* lines = nullptr) const;
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
    std::string canonical;  // the key this one is an alias of; empty = itself
    bool saved = true;      // written by ToYaml
  };
  const std::vector<Entry>& entries() const { return entries_; }

 private:
  void AddEntry(Entry entry);
  std::vector<Entry> entries_;
  std::vector<std::string> ignored_prefixes_;
};

// Runs `check` (options' Check() calls) and rethrows its errors as InputError of file `name`:
// a SettingError at the line of its key (0 when the key was not in the file, i.e. a default or
// a flag), any other Error at line 0.
void CheckWithKeyLines(const std::string& name, const SettingsTable::KeyLines& lines,
                       const std::function<void()>& check);

// Lines of OpenCV's 'key:value' (no space after the colon) rewritten as 'key: value'; a first
// '%YAML:1.0' line blanked. Line count and numbering are unchanged.
std::string NormalizeOpenCvYaml(const std::string& text);

}  // namespace esdslam
