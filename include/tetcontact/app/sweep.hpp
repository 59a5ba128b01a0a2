// `tetcontact sweep`: error against run time. The case is run once per combination of the
// varied keys, and every run's wall time, steps and error measures go to sweep.csv.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace tc {

struct SweepOptions {
  std::string case_path;
  /// key → values (YAML each), in the order given; the runs are their Cartesian product,
  /// the last key varying fastest.
  std::vector<std::pair<std::string, std::vector<std::string>>> vary;
  /// analytic: the case's declared references; finest: the run with the most tets (then the
  /// smallest cfl, the most passes, the later run) as the reference of every other; or the path of
  /// a summary.json from an earlier run.
  std::string reference = "analytic";
  std::string out_dir;  // default results/<case name>-sweep
  bool force = false;
  bool quiet = false;
  std::vector<std::string> overrides;  // --set, applied to every run
};

/// A CSV field: quoted (quotes doubled) when it holds a comma or a quote.
std::string csv_field(const std::string& s);

/// Splits "v1,v2,[a,b],v4" at the commas outside brackets and braces.
std::vector<std::string> split_values(const std::string& list);

/// Exit codes: 0 every run finished, 1 a run failed (its row says so), 2 bad input.
int sweep_command(const SweepOptions& options);

}  // namespace tc
