#pragma once
// Folders the tests read: the source tree, the build tree and ../shared (data and models).
// Defined in test_paths.cpp, the one test file compiled with the paths, so that the other test
// files do not depend on where the checkout lives.
#include <string>

namespace esdslam::testing {

std::string SourceDir();    // the project's source tree
std::string BinaryDir();    // the build tree (holds the esdslam program)
std::string TestDataDir();  // ../shared beside the checkout: data/ and models/

}  // namespace esdslam::testing
