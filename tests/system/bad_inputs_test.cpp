// The corpus of bad inputs (tests/data/bad_inputs, listed with their expected errors in
// EXPECTED.txt): every one gives an InputError naming its file, at the expected line, with the
// expected words, or is read with its bad entries skipped. The fuzz targets (fuzz/) search for
// new ones; a finding is added here once fixed.
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "common/error.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "map/core_test_scene.h"
#include "map/map.h"
#include "map/map_serialization.h"
#include "place/vocabulary.h"
#include "support/temp_path.h"
#include "support/test_paths.h"
#include "system/run_settings.h"

namespace esdslam {
namespace {

namespace fs = std::filesystem;

struct Case {
  std::string file;  // relative to tests/data/bad_inputs
  std::string line;  // a number, -1 (not checked) or "skip"
  std::string fragment;
};

std::string Trim(const std::string& text) {
  const auto b = text.find_first_not_of(" \t");
  const auto e = text.find_last_not_of(" \t\r");
  return b == std::string::npos ? std::string() : text.substr(b, e - b + 1);
}

std::string CorpusDir() { return ::esdslam::testing::SourceDir() + "/tests/data/bad_inputs"; }

std::vector<Case> ReadCases() {
  std::ifstream in(CorpusDir() + "/EXPECTED.txt");
  std::vector<Case> cases;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream fields(line);
    Case c;
    std::getline(fields, c.file, '|');
    std::getline(fields, c.line, '|');
    std::getline(fields, c.fragment);
    cases.push_back({Trim(c.file), Trim(c.line), Trim(c.fragment)});
  }
  return cases;
}

// A sequence folder whose rgb.txt (or association file) is `list`; depth.txt and the images
// that the valid entries name exist. Returns the number of frames Open() keeps.
std::size_t OpenList(const std::string& list, const std::string& name) {
  const std::string dir = testing::TestTempPath("bad_list_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir + "/rgb");
  fs::create_directories(dir + "/depth");
  for (const char* file : {"rgb/1.0.png", "rgb/1.png", "rgb/2.png", "depth/1.0.png", "depth/1.png", "depth/2.png"})
    std::ofstream(dir + "/" + file) << "x";
  AssociationOptions options;
  if (name.rfind("associations_", 0) == 0) {
    fs::copy_file(list, dir + "/list.txt");
    options.association_file = dir + "/list.txt";
  } else {
    fs::copy_file(list, dir + "/rgb.txt");
    std::ofstream(dir + "/depth.txt") << "1.0 depth/1.0.png\n1.01 depth/1.png\n2.0 depth/2.png\n";
  }
  return TumSequence::Open(dir, options).frames().size();
}

// Reads `path` with the reader its folder stands for; returns the frames kept (lists only).
std::size_t Read(const std::string& kind, const std::string& path) {
  if (kind == "settings") {
    LoadRunSettings(path);
  } else if (kind == "lists") {
    return OpenList(path, fs::path(path).stem().string());
  } else if (kind == "trajectory") {
    ReadTumTrajectory(path);
  } else if (kind == "map") {
    Map map;
    LoadMap(path, ::esdslam::testing::TestRig(), &map);
  } else if (kind == "vocabulary") {
    Vocabulary::Load(path);
  } else {
    ADD_FAILURE() << "no reader for folder " << kind;
  }
  return 0;
}

TEST(BadInputsTest, EveryInputGivesItsNamedErrorOrIsSkipped) {
  const std::vector<Case> cases = ReadCases();
  EXPECT_GE(cases.size(), 40u);
  for (const Case& c : cases) {
    const std::string path = CorpusDir() + "/" + c.file;
    ASSERT_TRUE(fs::exists(path)) << path;
    const std::string kind = fs::path(c.file).parent_path().string();
    if (c.line == "skip") {
      EXPECT_EQ(std::to_string(Read(kind, path)), c.fragment) << c.file;
      continue;
    }
    try {
      Read(kind, path);
      ADD_FAILURE() << c.file << ": accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(kind == "lists" ? std::string() : path), std::string::npos) << c.file << ": " << what;
      if (c.line != "-1") {
        EXPECT_EQ(std::to_string(e.line()), c.line) << c.file << ": " << what;
      }
      EXPECT_NE(what.find(c.fragment), std::string::npos) << c.file << ": " << what;
    } catch (const std::exception& e) {
      ADD_FAILURE() << c.file << ": not an InputError: " << e.what();
    }
  }
}

TEST(BadInputsTest, EveryCorpusFileIsListed) {
  std::set<std::string> listed;
  for (const Case& c : ReadCases()) listed.insert(c.file);
  for (const auto& entry : fs::recursive_directory_iterator(CorpusDir())) {
    if (!entry.is_regular_file() || entry.path().filename() == "EXPECTED.txt") continue;
    EXPECT_EQ(listed.count(fs::relative(entry.path(), CorpusDir()).string()), 1u) << entry.path();
  }
}

}  // namespace
}  // namespace esdslam
