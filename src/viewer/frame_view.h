#pragma once
// One frame as the browser sees it: decimated, encoded on the viewer thread, never on the
// tracking thread. The picture is the colour frame scaled by ViewerOptions::image_scale with the
// dynamic mask tinted in (semantic mask cyan, geometry mask magenta), as JPEG; keypoints are in
// the picture's pixels with their kind; the numbers come from the column table
// (system/frame_columns.h), so the panel shows what timing.csv records.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "system/frame_report.h"
#include "viewer/viewer_json.h"
#include "viewer/viewer_options.h"

namespace esdslam {

enum class KeypointKind : int { kKept = 0, kSemantic = 1, kGeometry = 2 };

struct ViewerKeypoint {
  float u = 0, v = 0;  // px in the scaled picture
  KeypointKind kind = KeypointKind::kKept;
};

// The run-wide numbers the viewer thread adds to a frame (it knows them, the report does not).
struct RunCounters {
  long frames = 0;         // frames processed so far (index + 1)
  long dropped = 0;        // frames the source dropped so far
  int keyframes = 0;       // live keyframes now
  int map_points = 0;      // live map points now
  double fps = 0;          // frames processed per second of run time
  long viewer_dropped = 0; // frames the viewer skipped (its queue was full)
};

// Scaled picture (CV_8UC3) with the masks tinted in. scale in (0, 1].
cv::Mat ViewerPicture(const FrameReport& report, double scale);
// The features' keypoints in picture px, thinned to max_keypoints (EvenSample).
std::vector<ViewerKeypoint> ViewerKeypoints(const FeatureSet& features, double scale, int max_keypoints);
// The frame event's JSON (one line): index, timestamp, state, counters, pose, every column of the
// table in "ms" (stages), keypoint counts, the JPEG (base64) and the keypoints.
std::string EncodeFrameEvent(const FrameReport& report, const RunCounters& counters, const ViewerOptions& options);
// The column part alone, from the values of every column (FrameColumns() order): "stages"
// (the columns in ms, by name), "columns" (the other numeric ones) and each text column (state).
void AppendColumnValues(const std::vector<double>& values, JsonText* json);

}  // namespace esdslam
