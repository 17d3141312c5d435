#include "support/test_paths.h"

namespace esdslam::testing {

std::string SourceDir() { return ESDSLAM_SOURCE_DIR; }
std::string BinaryDir() { return ESDSLAM_BINARY_DIR; }
std::string TestDataDir() { return ESDSLAM_TEST_DATA_DIR; }

}  // namespace esdslam::testing
