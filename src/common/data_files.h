#pragma once
// Where the program and the library find their data files (networks, the ORB vocabulary, the
// viewer's page) at run time. Nothing from the source tree is compiled in: a relative data path
// ("models/espnetv2_s2.0_voc_384x288.onnx", "tools/web") is looked for under these roots, in
// order:
//   1. `first_dir` (a settings file's folder), when given;
//   2. $ESDSLAM_DATA_DIR, when set;
//   3. the running program's folder, its parent and grandparent (a build tree inside the
//      sources: build/esdslam, build/tests/test_x);
//   4. <program folder>/../share/esdslam (an installed program);
//   5. when this code is in a shared library or a Python module: its folder's parent and
//      grandparent (build/python/esdslam*.so in a build tree), and share/esdslam one to three
//      folders up (the installed lib/libesdslam.so, lib/python3/dist-packages/esdslam*.so);
//   6. the install prefix's share/esdslam as configured at build time (CMAKE_INSTALL_PREFIX).
// The installed layout keeps the source tree's relative paths: share/esdslam/models/...,
// share/esdslam/tools/web/..., share/esdslam/config/*.yaml.

#include <string>
#include <vector>

namespace esdslam {

std::vector<std::string> DataRoots(const std::string& first_dir = "");

// `path` unchanged when empty, absolute or existing as given; else the first root holding it
// (canonical); else `path` unchanged (the caller then reports it as missing, with its name).
std::string FindDataPath(const std::string& path, const std::string& first_dir = "");

// $ESDSLAM_DATA_DIR when set, else the first existing share/esdslam among the roots (an
// installed program, library or module), else the configured install prefix's (root 6).
std::string InstalledDataDir();

}  // namespace esdslam
