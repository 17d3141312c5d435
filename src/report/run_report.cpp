#include "report/run_report.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "common/error.h"
#include "report/html.h"
#include "report/report_sections.h"

namespace esdslam {
namespace {

constexpr const char* kStyle = R"(<style>
body { font-family: sans-serif; margin: 24px auto; max-width: 1000px; color: #222; background: #fff; }
h1 { font-size: 24px; } h2 { font-size: 19px; border-bottom: 1px solid #ccc; padding-bottom: 4px; margin-top: 32px; }
figure { margin: 12px 0; } figcaption { font-size: 13px; color: #555; }
svg { max-width: 100%; height: auto; }
figure.topview svg { max-width: 540px; }
table { border-collapse: collapse; font-size: 13px; margin: 8px 0; }
th, td { border: 1px solid #ccc; padding: 3px 8px; text-align: left; }
td[data-metric] { font-family: monospace; text-align: right; }
table.settings td { font-family: monospace; }
.note { color: #8a4b00; }
.frames { display: flex; flex-wrap: wrap; gap: 12px; }
.debug-frame { width: 480px; }
.debug-frame img { max-width: 100%; height: auto; }
pre { background: #f6f6f6; padding: 8px; font-size: 12px; overflow-x: auto; }
</style>
)";

double FirstTime(const RunFiles& files) {
  if (files.timing.Has("timestamp")) {
    for (double t : files.timing.Numbers("timestamp"))
      if (std::isfinite(t)) return t;
  }
  return files.trajectory.empty() ? 0.0 : files.trajectory.front().timestamp;
}

std::string Header(const RunFiles& files, const ReportOptions& options) {
  std::string html = "<h1>ESD-SLAM run report</h1>\n<p>Run folder: <code>" + EscapeHtml(files.out_dir) + "</code>";
  if (!options.groundtruth_path.empty()) html += "<br>Ground truth: <code>" + EscapeHtml(options.groundtruth_path) + "</code>";
  html += "<br>Sections: <a href=\"#trajectory\">trajectory</a> &middot; <a href=\"#error\">error</a> &middot; "
          "<a href=\"#timing\">stage times</a> &middot; <a href=\"#debug\">debug frames</a> &middot; "
          "<a href=\"#summary\">summary</a> &middot; <a href=\"#settings\">settings</a></p>\n";
  return html;
}

}  // namespace

void ReportOptions::Check() const {
  if (out_dir.empty()) throw Error("report: the run folder is empty");
  if (max_debug_frames < 0 || max_debug_frames > 50)
    throw Error(fmt::format("report: max_debug_frames {}: expected 0..50", max_debug_frames));
  if (debug_frame_width_px < 64 || debug_frame_width_px > 4096)
    throw Error(fmt::format("report: debug_frame_width_px {}: expected 64..4096", debug_frame_width_px));
  if (!(crowded_fraction > 0 && crowded_fraction <= 1))
    throw Error(fmt::format("report: crowded_fraction {}: expected (0, 1]", crowded_fraction));
  ate.Check();
}

std::string BuildRunReportHtml(const RunFiles& files, const std::vector<StampedPose>* groundtruth,
                               const ReportOptions& options) {
  options.Check();
  ReportData data;
  data.files = &files;
  data.groundtruth = groundtruth;
  if (groundtruth != nullptr) {
    EvalOptions eval;
    eval.ate = options.ate;
    data.eval = Evaluate(*groundtruth, files.trajectory, eval);
  }
  data.t0 = FirstTime(files);
  data.crowded = CrowdedIntervals(files.timing, options.crowded_fraction, data.t0, &data.crowded_frames);
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                     "<title>ESD-SLAM run report</title>\n";
  html += kStyle;
  html += "</head>\n<body>\n" + Header(files, options) + TrajectorySection(data) + ErrorSection(data, options) +
          TimingSection(data, options) + DebugSection(data, options) + SummarySection(data, options) +
          SettingsSection(data) + "</body>\n</html>\n";
  return html;
}

std::string WriteRunReport(const ReportOptions& options) {
  options.Check();
  const RunFiles files = ReadRunFiles(options.out_dir, options.debug_frames_dir);
  std::vector<StampedPose> groundtruth;
  if (!options.groundtruth_path.empty()) groundtruth = ReadTumTrajectory(options.groundtruth_path);
  const std::string html =
      BuildRunReportHtml(files, options.groundtruth_path.empty() ? nullptr : &groundtruth, options);
  const std::string path = (std::filesystem::path(options.out_dir) / "report.html").string();
  std::ofstream out(path, std::ios::binary);
  out << html;
  out.close();
  if (!out) throw Error("cannot write " + path);
  return path;
}

}  // namespace esdslam
