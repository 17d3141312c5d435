#pragma once
// Shared by the libFuzzer targets (fuzz/*_fuzzer.cpp, built with -DESDSLAM_BUILD_FUZZERS=ON):
// the readers take paths, so each input is written to a per-process scratch file first. A
// target passes when the reader returns or throws esdslam::Error; anything else (another
// exception, a crash, a hang, a sanitizer report, a huge allocation) is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <spdlog/spdlog.h>

namespace esdslam::fuzz {

// A scratch folder for this process (created once), e.g. /tmp/esdslam_fuzz_<pid>/.
inline std::string ScratchDir() {
  static const std::string dir = [] {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("esdslam_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    spdlog::set_level(spdlog::level::off);  // readers warn about skipped lines; keep the output short
    return path.string();
  }();
  return dir;
}

inline std::string WriteScratch(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::string path = ScratchDir() + "/" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace esdslam::fuzz
