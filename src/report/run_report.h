#pragma once
// The run report (`esdslam report OUT`, `esdslam run --report`): OUT/report.html, one
// self-contained page (inline SVG charts, base64 PNG pictures, inline CSS; no script, no
// network, no other file) made from the run's files (report/run_files.h) and, when given, the
// ground truth:
//   - trajectory against ground truth: top view (X-Y, the estimate aligned as `esdslam eval`
//     aligns it) and x, y, z over time
//   - ATE error over time, with the frames where people cover most of the image shaded
//   - per-stage time over time and the dynamic fraction over time
//   - a few sampled debug pictures (masks and keypoints), or a note that there are none
//   - the summary table (the metrics `esdslam eval` prints, with the same digits; the per-frame
//     columns' statistics) and the effective settings
// Every number in a summary table carries data-metric="NAME" so that tests find it by name.

#include <string>
#include <vector>

#include "eval/ate.h"
#include "report/run_files.h"

namespace esdslam {

struct ReportOptions {
  std::string out_dir;           // the run's folder; the report is written there
  std::string groundtruth_path;  // TUM ground truth; empty = trajectory without accuracy
  std::string debug_frames_dir;  // the run's --debug-frames folder; empty = none
  int max_debug_frames = 4;      // pictures sampled into the page, 0..50
  int debug_frame_width_px = 480;  // each picture scaled to this width, 64..4096
  // A frame counts as crowded (shaded) when its dynamic_fraction exceeds this ("people cover
  // most of the image"), in (0, 1].
  double crowded_fraction = 0.5;
  AteOptions ate;           // association and alignment: the defaults of `esdslam eval`
  std::string run_summary;  // the run's end-of-run summary text, shown when given
  void Check() const;       // throws Error naming the field
};

// The page. groundtruth: nullptr = none. Reads the sampled debug pictures from disk.
// Throws Error when the ATE cannot be computed (fewer than 3 associated poses) or a picture
// cannot be read.
std::string BuildRunReportHtml(const RunFiles& files, const std::vector<StampedPose>* groundtruth,
                               const ReportOptions& options);

// Reads the run's files and the ground truth, writes OUT/report.html; returns its path.
std::string WriteRunReport(const ReportOptions& options);

}  // namespace esdslam
