// GoogleTest entry point of every test executable.
//
// ESDSLAM_TEST_SERIAL_OPENCV=1 makes OpenCV run its parallel loops on the calling thread
// (cv::setNumThreads(0)). The ThreadSanitizer job sets it: Debian's OpenCV runs parallel_for_ on
// TBB, which is not instrumented, so TSan would report the hand-over of rows between TBB workers
// and the caller as races. With OpenCV serial, the only threads left are the project's own
// (local mapping, segmentation, dense mapping), which is what the TSan job checks.
#include <cstdlib>
#include <cstring>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

int main(int argc, char** argv) {
  const char* serial = std::getenv("ESDSLAM_TEST_SERIAL_OPENCV");
  if (serial != nullptr && std::strcmp(serial, "0") != 0) cv::setNumThreads(0);
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
