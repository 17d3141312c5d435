#!/usr/bin/env bash
# ThreadSanitizer job: builds the tests that run the project's threads (bounded queues, the
# worker type every stage thread uses, the segmentation worker, the mask stage, the local mapper's pause, the
# dense mapper, and the whole pipeline with every thread: mask stage, segmentation, tracking, local mapping,
# loop closing, global BA, dense mapper; the viewer thread) with -fsanitize=thread and runs them. OpenCV's own parallel loops run serially here (ESDSLAM_TEST_SERIAL_OPENCV, see
# tests/support/test_main.cpp): Debian's OpenCV uses TBB, which TSan cannot see into.
# Add a test here when it starts a thread of ours.
set -euo pipefail
cd "$(dirname "$0")/.."
targets=(test_common test_io test_semantic test_dynamic test_mapping test_dense test_system test_viewer)
dir=build-tsan
ESDSLAM_BUILD_TARGETS="${targets[*]}" tools/build.sh tsan
export ESDSLAM_TEST_SERIAL_OPENCV=1
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 suppressions=$PWD/tools/tsan.supp"
"$dir/tests/test_common" --gtest_filter='BoundedQueue.*:Worker.*'
"$dir/tests/test_io" --gtest_filter='PrefetchingFrameSource*'
"$dir/tests/test_semantic" --gtest_filter='SegmentationWorker.*:ScopedLayerConstructor.*'
"$dir/tests/test_dynamic" --gtest_filter='MaskAhead.*:*/MaskAheadModes.*'
"$dir/tests/test_mapping" --gtest_filter='LocalMapperTest.*'
"$dir/tests/test_dense" --gtest_filter='DenseMapper.*'
"$dir/tests/test_system" --gtest_filter='SlamSystemTest.Threaded*:ThreadedPipelineTest.*:PipelineTest.PredictedMasksNeverWaitInAThreadedRun'
# The viewer thread and its hub; not the HTTP test (cpp-httplib is a prebuilt, uninstrumented library).
"$dir/tests/test_viewer" --gtest_filter='EventHub.*:LiveViewer.Offer*:LiveViewer.FrameInterval*'
echo "tsan: no data race reported"
