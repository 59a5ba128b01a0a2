// The house has no cycles: the stage folders stand in the order ARCHITECTURE.md writes down
// (its line "Folder order (lowest first): `mesh` → ..."), and every include of a file under
// include/tetcontact/F/ or src/F/ names F itself or a folder below it. A new folder must be
// placed in that order before anything may include it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "test_util.hpp"

namespace fs = std::filesystem;

namespace {

std::vector<std::string> folder_order() {
  std::ifstream in(tc::test::source_path("ARCHITECTURE.md"));
  std::vector<std::string> order;
  for (std::string line; std::getline(in, line);)
    if (line.rfind("Folder order (lowest first):", 0) == 0) {
      const std::regex name("`([a-z_]+)`");
      for (std::sregex_iterator it(line.begin(), line.end(), name), end; it != end; ++it)
        order.push_back((*it)[1]);
    }
  return order;
}

std::vector<std::string> subfolders(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_directory()) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(Architecture, FoldersIncludeOnlyThemselvesAndFoldersBelow) {
  const std::vector<std::string> order = folder_order();
  ASSERT_GE(order.size(), 10u) << "ARCHITECTURE.md has no 'Folder order (lowest first):' line";
  const auto rank = [&](const std::string& f) {
    return static_cast<long>(std::find(order.begin(), order.end(), f) - order.begin());
  };
  // Every folder of the sources is placed in the order.
  for (const fs::path& root : {fs::path(tc::test::source_path("src")),
                               fs::path(tc::test::source_path("include/tetcontact"))})
    for (const std::string& f : subfolders(root))
      EXPECT_LT(rank(f), static_cast<long>(order.size())) << root / f << " is not in the order";
  const std::regex include("#include \"tetcontact/([a-z_]+)/");
  long includes = 0;
  for (const std::string& folder : order)
    for (const fs::path& dir : {fs::path(tc::test::source_path("src/" + folder)),
                                fs::path(tc::test::source_path("include/tetcontact/" + folder))}) {
      if (!fs::is_directory(dir)) continue;
      for (const auto& e : fs::directory_iterator(dir)) {
        std::ifstream in(e.path());
        for (std::string line; std::getline(in, line);) {
          std::smatch m;
          if (!std::regex_search(line, m, include)) continue;
          ++includes;
          EXPECT_LE(rank(m[1]), rank(folder))
              << e.path().string() << " (" << folder << ") includes " << m[1] << ": " << line;
        }
      }
    }
  EXPECT_GT(includes, 100);  // the scan saw the sources
}

// The data layer is plain data: `model/` includes nothing above mesh and material, so every
// stage can depend on it without depending on another stage.
TEST(Architecture, ModelIsTheDataLayer) {
  const std::vector<std::string> order = folder_order();
  ASSERT_GE(order.size(), 4u);
  EXPECT_EQ(order[0], "parallel");  // threads: under everything, knows nothing of the physics
  EXPECT_EQ(order[1], "mesh");
  EXPECT_EQ(order[2], "material");
  EXPECT_EQ(order[3], "model");
  EXPECT_EQ(order.back(), "app");
}

// Detection lives in broadphase/ and narrowphase/; response/ only responds to the contact points
// it is given (the impulse kernel, walls, islands, impact zones): it includes neither.
TEST(Architecture, ResponseOnlyResponds) {
  const std::regex include("#include \"tetcontact/(broadphase|narrowphase)/");
  long files = 0;
  for (const fs::path& dir : {fs::path(tc::test::source_path("src/response")),
                              fs::path(tc::test::source_path("include/tetcontact/response"))})
    for (const auto& e : fs::directory_iterator(dir)) {
      ++files;
      std::ifstream in(e.path());
      for (std::string line; std::getline(in, line);)
        EXPECT_FALSE(std::regex_search(line, include)) << e.path().string() << ": " << line;
    }
  EXPECT_GE(files, 8);  // the scan saw the folder
}

// The project speaks of itself alone: no tracker numbers, no work-log words and no shorthand
// for the two papers in the manual, the sources, the tests, the tools or the case files (a
// paper is named by its authors). The words are spelled in pieces here so that this file does
// not find itself.
TEST(Architecture, NoTrackerNumbersOrLogWordsInTheTree) {
  const std::vector<std::regex> banned = {std::regex("\\biss"
                                                     "ues? #?[0-9]",
                                                     std::regex::icase),
                                          std::regex("\\bsess"
                                                     "ions?\\b",
                                                     std::regex::icase),
                                          std::regex("\\bse"
                                                     "ed (document|paper|0)",
                                                     std::regex::icase),
                                          std::regex("\\bse"
                                                     "eds? 0",
                                                     std::regex::icase)};
  const std::vector<std::string> extensions = {".md",   ".cpp",   ".hpp", ".py",
                                               ".yaml", ".cmake", ".txt"};
  std::vector<fs::path> files = {
      tc::test::source_path("README.md"), tc::test::source_path("ARCHITECTURE.md"),
      tc::test::source_path("CMakeLists.txt"), tc::test::source_path("Makefile"),
      tc::test::source_path("data/materials.yaml")};
  for (const char* root : {"docs", "src", "include", "tests", "tools", "bench", "data/cases"}) {
    const fs::path dir = tc::test::source_path(root);
    if (!fs::is_directory(dir)) continue;
    for (const auto& e : fs::recursive_directory_iterator(dir))
      if (e.is_regular_file() && std::find(extensions.begin(), extensions.end(),
                                           e.path().extension().string()) != extensions.end())
        files.push_back(e.path());
  }
  long lines = 0;
  for (const fs::path& file : files) {
    std::ifstream in(file);
    ASSERT_TRUE(in) << file;
    long number = 0;
    for (std::string line; std::getline(in, line);) {
      ++number;
      ++lines;
      for (const std::regex& word : banned)
        EXPECT_FALSE(std::regex_search(line, word))
            << file.string() << ":" << number << ": " << line;
    }
  }
  EXPECT_GT(lines, 20000);  // the scan saw the tree
}
