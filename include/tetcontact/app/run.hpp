// The subcommands: run a case, check a case.
#pragma once

#include <string>
#include <vector>

namespace tc {

struct RunOptions {
  std::string case_path;
  std::string out_dir;  // default: results/<case name>
  bool force = false;
  bool quiet = false;
  bool check = false;                  // exit 1 when a reference value of the case is missed
  std::vector<std::string> overrides;  // --set path=value
  /// --restart: a run folder (or its checkpoints folder, or one checkpoint file) to go on from
  /// its newest checkpoint, in that folder.
  std::string restart;
};

/// Exit codes: 0 success, 2 bad input (nothing written), 1 run failure (summary says why).
int run_case(const RunOptions& options);
int check_case(const RunOptions& options);

}  // namespace tc
