// The per-frame column table: timing.csv's header and rows from hand-filled reports, the
// summary's per-stage lines, reading columns by name, and the README's timing.csv table.
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "common/error.h"
#include "support/temp_path.h"
#include "support/test_paths.h"
#include "system/frame_columns.h"
#include "system/frame_log.h"

namespace esdslam {
namespace {

// The timing.csv header as readers (the viewer, reports, scripts) know it.
const char* kHeader =
    "timestamp,load_ms,extract_ms,track_ms,state,lost,seg_latency_ms,seg_wait_ms,mask_ms,label_age,"
    "dynamic_fraction,keypoints,dynamic_keypoints,grow_ms,geometry_ms,geometry_keypoints,geometry_culled,"
    "geometry_covered,geometry_window_px,grow_cpu_ms,geometry_cpu_ms,dropped_before,predict_ms,predict_cpu_ms,label_trust,"
    "mask_wait_ms,inliers,new_keyframe,coasted";

// Every field a column reads, each a different value.
FrameReport HandFilledReport() {
  FrameReport r;
  r.index = 7;
  r.timestamp = 1305031102.175304;
  r.load_ms = 12.3456;
  r.dropped_before = 3;
  r.mask.source_id = 5;  // label age 2
  r.mask.latency_ms = 140.25;
  r.mask.wait_ms = 3.5;
  r.mask.refine_ms = 1.75;
  r.mask.grow_ms = 0.5;
  r.mask.grow_cpu_ms = 0.25;
  r.mask.dynamic_fraction = 0.123456;
  r.mask_wait_ms = 0.75;
  r.track.state = TrackingState::kOk;
  r.track.has_pose = true;
  r.track.extract_ms = 9.875;
  r.track.track_ms = 17.0624;
  r.track.geometry.check_ms = 2.125;
  r.track.geometry.check_cpu_ms = 2.0;
  r.track.geometry.points_culled = 4;
  r.track.geometry.covered = 31;
  r.track.geometry.window_radius_px = 3;
  r.track.inliers = 321;
  r.track.new_keyframe = true;
  r.keypoints = {1000, 120, 20};
  return r;
}

TEST(FrameColumnsTest, CsvHeaderAndRowFromAHandFilledReport) {
  EXPECT_EQ(FrameCsvHeader(), kHeader);
  EXPECT_EQ(FrameCsvRow(ReadFrameColumns(HandFilledReport())),
            "1305031102.175304,12.346,9.875,17.062,OK,0,140.250,3.500,1.750,2,0.1235,1000,120,0.500,2.125,20,4,31,3,"
            "0.250,2.000,3,0.000,0.000,1.000,0.750,321,1,0");
}

TEST(FrameColumnsTest, EmptyStagesLostFramesAndSkippedChecks) {
  FrameReport r;  // no labels, no pose, the check skipped the frame (too fast)
  r.track.state = TrackingState::kLost;
  r.track.geometry.skipped_fast_motion = true;
  r.track.geometry.window_radius_px = 5;
  const std::vector<double> values = ReadFrameColumns(r);
  EXPECT_EQ(values[FrameColumnIndex("label_age")], -1);
  EXPECT_EQ(values[FrameColumnIndex("lost")], 1);
  EXPECT_EQ(values[FrameColumnIndex("geometry_window_px")], -1);
  EXPECT_EQ(FindFrameColumn("state").Format(values[FrameColumnIndex("state")]), "LOST");
  EXPECT_THROW(FindFrameColumn("no_such_column"), Error);
  EXPECT_THROW(FrameCsvRow({1.0, 2.0}), Error);
}

TEST(FrameColumnsTest, LogWritesTheCsvAndReadsColumnsByName) {
  FrameLog log;
  FrameReport first = HandFilledReport();
  FrameReport second = HandFilledReport();
  second.index = 8;
  second.load_ms = 20;
  second.track.has_pose = false;
  log.Add(first);
  log.Add(second);
  EXPECT_EQ(log.Values("load_ms"), (std::vector<double>{first.load_ms, 20.0}));
  EXPECT_EQ(log.Values("label_age"), (std::vector<double>{2, 3}));
  EXPECT_DOUBLE_EQ(log.Values("dynamic_ms")[0], 0.5 + 2.125);  // summary-only: grow + geometry
  const std::string path = testing::TestTempPath("frame_log", ".csv");
  log.WriteCsv(path);
  std::ifstream in(path);
  std::string header, row1, row2, extra;
  std::getline(in, header), std::getline(in, row1), std::getline(in, row2);
  EXPECT_EQ(header, kHeader);
  EXPECT_EQ(row1, FrameCsvRow(ReadFrameColumns(first)));
  EXPECT_EQ(row2.substr(0, 25), "1305031102.175304,20.000,");
  EXPECT_FALSE(std::getline(in, extra));
}

TEST(FrameColumnsTest, SummaryLinesInTableOrderWithMeanAndMedian) {
  FrameLog log;
  for (const double load : {1.0, 2.0, 6.0}) {
    FrameReport r = HandFilledReport();
    r.load_ms = load;
    log.Add(r);
  }
  std::istringstream lines(FormatStageSummary(log));
  std::vector<std::string> labels;
  std::string line, first;
  while (std::getline(lines, line)) {
    if (first.empty()) first = line;
    labels.push_back(line.substr(0, line.find(' ')));
  }
  EXPECT_EQ(first, "load     mean    3.00 ms  median    2.00 ms");
  EXPECT_EQ(labels, (std::vector<std::string>{"load", "extract", "track", "seg_lat", "seg_wait", "mask", "grow",
                                              "geometry", "predict", "mask_wait", "grow+geo", "(cpu)"}));
  EXPECT_EQ(ComputeMeanMedian({}).mean, 0);
  EXPECT_EQ(ComputeMeanMedian({4, 1, 3, 2}).median, 3);  // upper middle, as the summary always had
}

// The README's timing.csv table documents every CSV column, in order.
TEST(FrameColumnsTest, ReadmeDocumentsEveryCsvColumnInOrder) {
  std::ifstream in(testing::SourceDir() + "/README.md");
  ASSERT_TRUE(in) << "README.md";
  std::vector<std::string> documented;
  std::string line;
  bool in_table = false;
  while (std::getline(in, line)) {
    if (line.rfind("| timing.csv column", 0) == 0) in_table = true;
    else if (in_table && line.rfind("| `", 0) == 0) documented.push_back(line.substr(3, line.find('`', 3) - 3));
    else if (in_table && line.rfind("|", 0) != 0) break;
  }
  std::vector<std::string> columns;
  for (const FrameColumn& column : FrameColumns())
    if (column.csv) columns.push_back(column.name);
  EXPECT_EQ(documented, columns);
}

}  // namespace
}  // namespace esdslam
