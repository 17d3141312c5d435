#include "common/data_files.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>

#ifndef ESDSLAM_INSTALL_DATADIR
#define ESDSLAM_INSTALL_DATADIR "/usr/local/share/esdslam"
#endif

namespace esdslam {
namespace fs = std::filesystem;
namespace {

fs::path ExecutableDir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

// The folder of the binary (program or shared library) this function is linked into.
fs::path ThisBinaryDir() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&ThisBinaryDir), &info) == 0 || info.dli_fname == nullptr) return {};
  std::error_code ec;
  const fs::path binary = fs::canonical(info.dli_fname, ec);
  return ec ? fs::path() : binary.parent_path();
}

std::string EnvDataDir() {
  const char* dir = std::getenv("ESDSLAM_DATA_DIR");
  return dir != nullptr ? std::string(dir) : std::string();
}

}  // namespace

std::vector<std::string> DataRoots(const std::string& first_dir) {
  std::vector<std::string> roots;
  if (!first_dir.empty()) roots.push_back(first_dir);
  if (const std::string env = EnvDataDir(); !env.empty()) roots.push_back(env);
  const fs::path exe_dir = ExecutableDir();
  if (!exe_dir.empty()) {
    roots.push_back(exe_dir.string());
    roots.push_back((exe_dir / "..").string());
    roots.push_back((exe_dir / ".." / "..").string());
    roots.push_back((exe_dir / ".." / "share" / "esdslam").string());
  }
  const fs::path binary_dir = ThisBinaryDir();
  if (!binary_dir.empty() && binary_dir != exe_dir) {  // a shared library or a Python module
    roots.push_back((binary_dir / "..").string());
    roots.push_back((binary_dir / ".." / "..").string());
    fs::path up = binary_dir;  // lib/ or lib/python3/dist-packages/ under the prefix
    for (int level = 0; level < 3; ++level) roots.push_back(((up /= "..") / "share" / "esdslam").string());
  }
  roots.emplace_back(ESDSLAM_INSTALL_DATADIR);
  return roots;
}

std::string FindDataPath(const std::string& path, const std::string& first_dir) {
  std::error_code ec;
  if (path.empty() || fs::path(path).is_absolute() || fs::exists(path, ec)) return path;
  for (const std::string& root : DataRoots(first_dir)) {
    const fs::path candidate = fs::path(root) / path;
    if (fs::exists(candidate, ec)) return fs::weakly_canonical(candidate, ec).string();
  }
  return path;
}

std::string InstalledDataDir() {
  const std::string env = EnvDataDir();
  if (!env.empty()) return env;
  std::error_code ec;
  for (const std::string& root : DataRoots()) {  // an install found from the binaries' places
    const fs::path dir(root);
    if (dir.filename() == "esdslam" && dir.parent_path().filename() == "share" && fs::is_directory(dir, ec))
      return fs::weakly_canonical(dir, ec).string();
  }
  return ESDSLAM_INSTALL_DATADIR;
}

}  // namespace esdslam
