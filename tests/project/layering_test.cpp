// The README's layering table is true: every `#include "stage/..."` in src/ is allowed by the
// table's "uses" column, every folder listed there is used by some include, each used folder is
// listed above, and CMakeLists.txt's esdslam_stage(... DEPS ...) lists exactly the same folders.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/test_paths.h"

namespace esdslam {
namespace {

namespace fs = std::filesystem;
using StageDeps = std::map<std::string, std::set<std::string>>;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::set<std::string> SplitList(const std::string& text) {
  std::set<std::string> items;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (!item.empty()) items.insert(item);
  }
  return items;
}

// Rows of the table under "## Layering": | `stage/` | what | uses |, in table order.
std::vector<std::pair<std::string, std::set<std::string>>> ReadmeTable() {
  const std::string readme = ReadFile(fs::path(testing::SourceDir()) / "README.md");
  const std::size_t section = readme.find("## Layering");
  std::vector<std::pair<std::string, std::set<std::string>>> rows;
  if (section == std::string::npos) return rows;
  std::stringstream lines(readme.substr(section));
  const std::regex row(R"(^\| `([a-z_]+)/` \|[^|]*\|([^|]*)\|\s*$)");
  std::string line;
  std::smatch match;
  while (std::getline(lines, line)) {
    if (line.rfind("## ", 0) == 0 && !rows.empty()) break;
    if (std::regex_match(line, match, row)) rows.emplace_back(match[1], SplitList(match[2]));
  }
  return rows;
}

std::set<std::string> SourceStages() {
  std::set<std::string> stages;
  for (const auto& entry : fs::directory_iterator(fs::path(testing::SourceDir()) / "src"))
    if (entry.is_directory()) stages.insert(entry.path().filename().string());
  return stages;
}

// stage -> the other stages its files include (quoted includes "stage/file.h").
StageDeps IncludedStages(const std::set<std::string>& stages, std::vector<std::string>* includes_by_file) {
  StageDeps used;
  const std::regex include(R"(^\s*#\s*include\s+"([a-z_]+)/[^"]+")");
  for (const std::string& stage : stages) {
    used[stage];
    for (const auto& entry : fs::directory_iterator(fs::path(testing::SourceDir()) / "src" / stage)) {
      std::ifstream in(entry.path());
      std::string line;
      int number = 0;
      std::smatch match;
      while (std::getline(in, line)) {
        ++number;
        if (!std::regex_search(line, match, include) || match[1] == stage || !stages.count(match[1])) continue;
        used[stage].insert(match[1]);
        includes_by_file->push_back(stage + " " + match[1].str() + " " + entry.path().filename().string() + ":" +
                                    std::to_string(number));
      }
    }
  }
  return used;
}

StageDeps CmakeDeps() {
  const std::string cmake = ReadFile(fs::path(testing::SourceDir()) / "CMakeLists.txt");
  const std::regex stage_call(R"(esdslam_stage\(([a-z_]+)\s*(DEPS([^)]*))?\))");
  StageDeps deps;
  for (auto it = std::sregex_iterator(cmake.begin(), cmake.end(), stage_call); it != std::sregex_iterator(); ++it) {
    std::set<std::string>& list = deps[(*it)[1]];
    std::stringstream words((*it)[3].str());
    std::string word;
    while (words >> word) list.insert(word);
  }
  return deps;
}

class LayeringTest : public ::testing::Test {
 protected:
  void SetUp() override {
    rows_ = ReadmeTable();
    for (const auto& [stage, deps] : rows_) table_[stage] = deps;
    stages_ = SourceStages();
  }
  std::vector<std::pair<std::string, std::set<std::string>>> rows_;
  StageDeps table_;
  std::set<std::string> stages_;
};

TEST_F(LayeringTest, TableListsEverySourceFolderOnce) {
  ASSERT_FALSE(rows_.empty()) << "no layering table in README.md";
  EXPECT_EQ(rows_.size(), table_.size()) << "a folder appears twice in the table";
  for (const std::string& stage : stages_) EXPECT_TRUE(table_.count(stage)) << "src/" << stage << " is not in the table";
  for (const auto& [stage, deps] : table_) EXPECT_TRUE(stages_.count(stage)) << stage << "/ is in the table but not in src/";
}

TEST_F(LayeringTest, UsedFoldersAreListedAbove) {
  std::set<std::string> above;
  for (const auto& [stage, deps] : rows_) {
    for (const std::string& dep : deps) EXPECT_TRUE(above.count(dep)) << stage << " uses " << dep << ", not listed above it";
    above.insert(stage);
  }
}

TEST_F(LayeringTest, EveryIncludeIsAllowedAndEveryListedFolderIsUsed) {
  std::vector<std::string> includes;
  const StageDeps used = IncludedStages(stages_, &includes);
  for (const std::string& line : includes) {
    std::stringstream words(line);
    std::string stage, dep, where;
    words >> stage >> dep >> where;
    EXPECT_TRUE(table_[stage].count(dep)) << "src/" << stage << "/" << where << " includes " << dep
                                          << "/, which the README table does not allow for " << stage;
  }
  for (const auto& [stage, deps] : table_) {
    for (const std::string& dep : deps) {
      const auto it = used.find(stage);
      EXPECT_TRUE(it != used.end() && it->second.count(dep))
          << "the table lets " << stage << " use " << dep << ", but no file of src/" << stage << " includes it";
    }
  }
}

TEST_F(LayeringTest, CmakeDepsEqualTheTable) {
  const StageDeps cmake = CmakeDeps();
  for (const auto& [stage, deps] : table_) {
    const auto it = cmake.find(stage);
    ASSERT_TRUE(it != cmake.end()) << "no esdslam_stage(" << stage << ") in CMakeLists.txt";
    EXPECT_EQ(it->second, deps) << "CMake DEPS of " << stage << " differ from the README table";
  }
  EXPECT_EQ(cmake.size(), table_.size());
}

}  // namespace
}  // namespace esdslam
