// Checkpoint files: a run's complete state between two steps (what Simulation::persist and the
// observers' persist write, model/archive.hpp), under a header that says which build of the
// program and which inputs wrote it, so that a restart from another's is refused.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace tc {

/// A checkpoint that cannot be used: none there, another build's, another case's, damaged. The
/// message names the file.
struct CheckpointError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// What a checkpoint says of itself.
struct CheckpointHeader {
  std::string program;  // the build that wrote it (program_identity)
  std::string inputs;   // the 16-hex hash of the run's complete inputs (run_key)
  long step = 0;        // the steps taken
  double t = 0.0;       // the time reached, s
};

/// A run folder's checkpoints: DIR/checkpoints.
std::string checkpoint_folder(const std::string& run_dir);

/// Writes `payload` under `header` as DIR/checkpoints/step_NNNNNNNNNN.ckpt, atomically (a file
/// that is there is whole), then removes the oldest beyond the newest `keep`. Returns its path.
std::string write_checkpoint(const std::string& run_dir, const CheckpointHeader& header,
                             const std::string& payload, int keep);

/// The checkpoint files of a run folder, oldest first.
std::vector<std::string> checkpoint_files(const std::string& run_dir);

struct Checkpoint {
  std::string path;
  CheckpointHeader header;
  std::string payload;
};

/// The newest whole checkpoint of `where` (a run folder, its checkpoints folder, or one
/// checkpoint file, which must be whole), written by `program` for `inputs`; else
/// CheckpointError naming the file and what differs. In a folder a damaged newest one (cut
/// short, its checksum wrong) gives way to the one before, said in `skipped`.
Checkpoint read_checkpoint(const std::string& where, const std::string& program,
                           const std::string& inputs, std::vector<std::string>* skipped = nullptr);

/// The run folder a `--restart` argument names (the folder holding the checkpoints folder).
std::string restart_run_folder(const std::string& where);

}  // namespace tc
