// Helpers shared by the tests: paths, temporary folders, running the CLI.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tc::test {

inline std::string source_path(const std::string& rel) {
  return std::string(TETCONTACT_SOURCE_DIR) + "/" + rel;
}

/// A fresh folder under the build tree's test-output/, removed on destruction.
class TempDir {
 public:
  explicit TempDir(const std::string& name) {
    path_ = std::filesystem::absolute("test-output") / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string str() const { return path_.string(); }
  std::string operator/(const std::string& rel) const { return (path_ / rel).string(); }

 private:
  std::filesystem::path path_;
};

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

using Json = nlohmann::ordered_json;

/// A JSON file read with the library; a missing or malformed file throws (the test fails).
inline Json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": missing");
  return Json::parse(in);
}

/// The number at a JSON pointer ("/energy/balance_error_max"). A missing key or a null (not
/// measured) throws: a check never passes on a value that is not there.
inline double number(const Json& j, const std::string& pointer) {
  const Json& v = j.at(Json::json_pointer(pointer));
  if (!v.is_number()) throw std::runtime_error(pointer + " is not a number: " + v.dump());
  return v.get<double>();
}

struct CliResult {
  int code = -1;
  std::string out, err;
};

/// Runs `tetcontact ARGS` (ARGS already shell-quoted) and captures exit code, stdout, stderr.
inline CliResult run_cli(const std::string& args, const std::string& scratch) {
  const std::string out = scratch + "/.stdout", err = scratch + "/.stderr";
  const std::string cmd = std::string("'") + TETCONTACT_BINARY + "' " + args + " >'" + out +
                          "' 2>'" + err + "' </dev/null";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

/// A CSV file with a header row (predictions.csv, gauges.csv) as rows of column → value; no
/// field of the tests' files holds a quoted comma.
inline std::vector<std::map<std::string, std::string>> read_csv(const std::string& path) {
  std::istringstream in(read_text(path));
  const auto fields = [](const std::string& row) {
    std::vector<std::string> f;
    std::stringstream ss(row);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    if (!row.empty() && row.back() == ',') f.emplace_back();
    return f;
  };
  std::string row;
  std::getline(in, row);
  const std::vector<std::string> header = fields(row);
  std::vector<std::map<std::string, std::string>> out;
  while (std::getline(in, row)) {
    const std::vector<std::string> f = fields(row);
    if (f.size() != header.size())
      throw std::runtime_error(path + ": a row of " + std::to_string(f.size()) + " fields under " +
                               std::to_string(header.size()) + " columns: " + row);
    std::map<std::string, std::string> m;
    for (std::size_t i = 0; i < f.size(); ++i) m[header[i]] = f[i];
    out.push_back(m);
  }
  return out;
}

/// history.csv without its wall-clock columns (seconds_*).
inline std::string history_without_timings(const std::filesystem::path& file) {
  std::istringstream in(read_text(file.string()));
  std::string line, out;
  std::vector<bool> keep;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    if (keep.empty())
      for (const std::string& c : cells) keep.push_back(c.rfind("seconds_", 0) != 0);
    for (std::size_t i = 0; i < cells.size() && i < keep.size(); ++i)
      if (keep[i]) out += cells[i] + ",";
    out += "\n";
  }
  return out;
}

}  // namespace tc::test
