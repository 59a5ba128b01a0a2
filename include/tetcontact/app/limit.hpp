// `tetcontact limit`: the ballistic limit of a case by bracketing. A case key (a
// projectile's diameter, or the speed) is narrowed between two values where a criterion flips
// (perforated or not) to a stated tolerance, for each value of a second key (the speed: the
// curve), running the case in parallel processes and keeping every run.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace tc {

struct LimitOptions {
  std::string case_path;
  std::string find;  // the key narrowed, e.g. parameters.d
  double lo = 0.0, hi = 0.0;
  std::string criterion;  // perforated:BODY — the case's `perforated` measure of that body
  /// At most one key with its values (--vary KEY2=v1,v2,...): one bracket per value.
  std::vector<std::pair<std::string, std::vector<std::string>>> vary;
  int jobs = 0;             // processes at once; 0: the machine's cores
  double tolerance = 0.05;  // the bracket's width relative to its upper end
  std::string out_dir;      // default results/<case name>-limit
  bool quiet = false;
  /// --check: the case at both ends of the bracket, at each --vary value, checked as `tetcontact
  /// check` does (the file, the keys, the meshes, the first step); nothing runs, nothing written.
  bool check = false;
  std::vector<std::string> overrides;  // --set, applied to every run
};

/// Runs DIR/runs/<KEY2=w>/<KEY=x>_<hash>/ (each a `tetcontact run`, its summary.json kept; the
/// folder's name and its run.key hold the run's complete inputs — the program's build, the case
/// file, every override and the library: run_key —, and a finished run of the same inputs is read
/// back, not run again: an interrupted search resumes, and a search with another --set or by
/// another build runs anew beside it) and writes
/// DIR/limit.csv, a line per bracket. Exit codes: 0 every bracket found, 1 one was not (both
/// ends alike, or a run failed: its line says which), 2 bad input (nothing run).
int limit_command(const LimitOptions& options);

}  // namespace tc
