#pragma once
// Range checks of settings values: options' Check() functions name the settings key of a value,
// so that the loader can report the file and line where the key was given
// (io/settings_table.h CheckWithKeyLines).

#include <string>

#include "common/error.h"

namespace esdslam {

// A settings value that fails its check. key() is the settings key ("Dense.voxelSize"), so that
// a loader can add the file and line where the key was given (io/settings_table.h).
class SettingError : public Error {
 public:
  SettingError(const std::string& key, const std::string& what) : Error(what), key_(key) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

// Throws SettingError naming `key` unless min <= value <= max (NaN fails). `unit` is appended
// to the bounds in the message ("m", "px", ...).
template <typename T>
void CheckRange(const std::string& key, T value, T min, T max, const char* unit = "") {
  if (value >= min && value <= max) return;
  const std::string suffix = *unit ? std::string(" ") + unit : std::string();
  throw SettingError(key, fmt::format("{} must be in [{}, {}]{}, got {}", key, min, max, suffix, value));
}

// Throws SettingError(key, message) unless `ok` (for checks that relate two keys).
inline void CheckSetting(bool ok, const std::string& key, const std::string& message) {
  if (!ok) throw SettingError(key, key + ": " + message);
}


}  // namespace esdslam
