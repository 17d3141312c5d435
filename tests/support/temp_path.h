#pragma once
// Paths for files and folders that tests write. ctest runs every test in its own process, in
// parallel, so a fixed name under /tmp would be shared by concurrent processes: each path here
// carries the process id. What a test process creates there is removed when it exits.
#include <unistd.h>

#include <filesystem>
#include <mutex>
#include <string>
#include <system_error>
#include <vector>

namespace esdslam::testing {

class TempPaths {
 public:
  static TempPaths& Instance() {
    static TempPaths paths;
    return paths;
  }
  std::string Make(const std::string& name, const std::string& extension) {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("esdslam_" + name + "_" + std::to_string(::getpid()) + extension);
    std::lock_guard<std::mutex> lock(mutex_);
    made_.push_back(path);
    return path.string();
  }
  ~TempPaths() {
    std::error_code ignored;
    for (const std::filesystem::path& path : made_) std::filesystem::remove_all(path, ignored);
  }

 private:
  std::mutex mutex_;
  std::vector<std::filesystem::path> made_;
};

// temp_dir/esdslam_<name>_<pid><extension> (a file or a folder), removed at process exit.
inline std::string TestTempPath(const std::string& name, const std::string& extension = "") {
  return TempPaths::Instance().Make(name, extension);
}

}  // namespace esdslam::testing
