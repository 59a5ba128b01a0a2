// Output directories and atomic file writes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>

namespace tc {

/// An output path that cannot be used (exists and is not empty, not writable): exit code 2.
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Creates `dir` (and parents). An existing non-empty directory is refused unless `force`,
/// in which case the files a previous run wrote there (case.pvd, frame_*.vtu, history.csv,
/// gauges.csv, summary.json, the checkpoints folder) are removed first so that no stale frame
/// or checkpoint survives; other files are kept.
void prepare_output_dir(const std::string& dir, bool force);

/// Writes `content` to `path` through a temporary file renamed into place.
void write_file_atomic(const std::string& path, const std::string& content);

/// A file written incrementally under a temporary name and renamed on commit().
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  ~AtomicFile();  // an uncommitted file is removed
  std::ofstream& stream() { return out_; }
  void commit();
  /// What has been written so far (flushed first).
  std::string written();
  /// Starts the file again with `content` (a run restarted from a checkpoint).
  void rewrite(const std::string& content);

 private:
  std::string path_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

/// The folder of tetcontact's data (materials.yaml, cases/): $TETCONTACT_DATA when set, else
/// `data` beside the folder of the running program (build/tetcontact finds the source tree's
/// data/), else `data` beside the program itself. No source path is compiled in: the program
/// works from a copied or moved tree. Throws std::runtime_error naming the places looked at.
std::string data_dir();

/// The 64-bit FNV-1a hash of bytes added in pieces, as 16 hex digits (keys of runs and
/// checkpoints; not a cryptographic hash).
struct Fnv1a {
  std::uint64_t h = 14695981039346656037ull;
  void add(const char* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
      h = (h ^ static_cast<unsigned char>(p[i])) * 1099511628211ull;
  }
  std::string hex() const;
};

/// Shortest decimal form that reads back to the same double ("nan"/"inf" for non-finite).
std::string format_double(double v);

}  // namespace tc
