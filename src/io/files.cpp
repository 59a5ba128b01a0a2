#include "tetcontact/io/files.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <sstream>

namespace tc {

namespace fs = std::filesystem;

std::string data_dir() {
  if (const char* env = std::getenv("TETCONTACT_DATA"); env && *env) {
    if (!fs::is_directory(env))
      throw std::runtime_error(std::string("TETCONTACT_DATA=") + env + ": not a directory");
    return env;
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  std::string looked;
  if (!ec)
    for (const fs::path& d :
         {exe.parent_path().parent_path() / "data", exe.parent_path() / "data"}) {
      if (fs::is_regular_file(d / "materials.yaml")) return d.string();
      looked += (looked.empty() ? "" : ", ") + d.string();
    }
  throw std::runtime_error("tetcontact's data folder not found (looked at " + looked +
                           "); set TETCONTACT_DATA to the tree's data/ folder");
}

void prepare_output_dir(const std::string& dir, bool force) {
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) throw OutputError(dir + ": exists and is not a directory");
    if (!fs::is_empty(dir, ec)) {
      if (!force)
        throw OutputError(dir +
                          ": output directory is not empty; choose another --out or pass "
                          "--force to replace the results of a previous run");
      static const std::regex ours(
          R"((case\.pvd|frame_\d+(_r\d+)?\.vtu|frame_\d+\.pvtu|particles\.pvd|particles_\d+\.vtu|history\.csv|gauges\.csv|summary\.json|sweep\.csv)(\.tmp)?)");
      for (const auto& entry : fs::directory_iterator(dir))
        if (entry.is_regular_file() && std::regex_match(entry.path().filename().string(), ours))
          fs::remove(entry.path());
      // A previous run's checkpoints: a restart must not go on from another run's state.
      fs::remove_all(dir + "/checkpoints", ec);
    }
  }
  fs::create_directories(dir, ec);
  if (ec) throw OutputError(dir + ": cannot create output directory: " + ec.message());
}

void write_file_atomic(const std::string& path, const std::string& content) {
  AtomicFile f(path);
  f.stream() << content;
  f.commit();
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), tmp_(path_ + ".tmp") {
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) throw OutputError(tmp_ + ": cannot open for writing");
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    out_.close();
    std::error_code ec;
    fs::remove(tmp_, ec);
  }
}

void AtomicFile::commit() {
  out_.flush();
  if (!out_) throw OutputError(tmp_ + ": write failed");
  out_.close();
  std::error_code ec;
  fs::rename(tmp_, path_, ec);
  if (ec) throw OutputError(path_ + ": cannot rename into place: " + ec.message());
  committed_ = true;
}

std::string AtomicFile::written() {
  out_.flush();
  if (!out_) throw OutputError(tmp_ + ": write failed");
  std::ifstream in(tmp_, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw OutputError(tmp_ + ": cannot read back");
  return text.str();
}

void AtomicFile::rewrite(const std::string& content) {
  out_.close();
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  out_ << content;
  if (!out_) throw OutputError(tmp_ + ": cannot write");
}

std::string Fnv1a::hex() const {
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

std::string format_double(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, p);
}

}  // namespace tc
