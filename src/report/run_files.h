#pragma once
// A finished run's output folder as the report reads it (the files of system/run_outputs.h):
//   OUT/trajectory.txt     required (TUM, world_from_cam)
//   OUT/keyframes.txt      optional
//   OUT/timing.csv         required; columns found by name (system/frame_columns.h), any order
//   OUT/settings_used.yaml optional; flat 'key: value' lines
//   debug pictures         optional; DIR/<timestamp>.png (system/run_outputs.h WriteDebugFrame)

#include <string>
#include <utility>
#include <vector>

#include "io/trajectory_io.h"

namespace esdslam {

// timing.csv as text cells (the state column is text), with numeric access by column name.
struct TimingTable {
  std::vector<std::string> columns;             // the header
  std::vector<std::vector<std::string>> rows;   // one per frame, as many cells as columns
  bool Has(const std::string& name) const;
  // The named column as numbers, NaN where a cell is not a number. Throws Error on an unknown name.
  std::vector<double> Numbers(const std::string& name) const;
  std::vector<std::string> Text(const std::string& name) const;  // throws Error on an unknown name
};

// Throws InputError naming the file (and line) when it is missing, has no header, or a row has
// a different number of cells than the header.
TimingTable ReadTimingCsv(const std::string& path);

// Flat 'key: value' lines; '%', '#' and blank lines skipped. Throws InputError on a line without
// ': ' or a missing file.
std::vector<std::pair<std::string, std::string>> ReadFlatYaml(const std::string& path);

struct DebugPicture {
  double timestamp = 0;  // seconds, from the file name
  std::string path;
};

// DIR/<timestamp>.png sorted by time; other files ignored; an absent folder gives none.
std::vector<DebugPicture> ListDebugPictures(const std::string& dir);

struct RunFiles {
  std::string out_dir;
  std::vector<StampedPose> trajectory;
  std::vector<StampedPose> keyframes;  // empty when keyframes.txt is absent
  TimingTable timing;
  std::vector<std::pair<std::string, std::string>> settings;  // empty when settings_used.yaml is absent
  std::vector<DebugPicture> debug_pictures;
};

// debug_dir: where the run wrote its debug pictures; empty = none. Throws as the readers above.
RunFiles ReadRunFiles(const std::string& out_dir, const std::string& debug_dir);

}  // namespace esdslam
