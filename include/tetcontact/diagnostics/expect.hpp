// A case's stated bounds (`expect:`), judged against the figures of a run: one list of the
// figures a bound may name (read by the case reader) and one code path that judges them (for
// `run --check` and the micro-scenes of `stress`).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tetcontact/diagnostics/penetration.hpp"

namespace tc {

/// What a run measured that a bound may name.
struct ExpectFigures {
  double momentum_error = 0.0;               // relative, over the run
  double energy_balance = 0.0;               // the balance's largest relative error
  std::optional<Penetration> penetration;    // maxima over the measures (none: not measured)
  std::optional<long> particles_inside_end;  // particle centres inside a body at the end
};

/// The figures an `expect:` bound may name, in the order judge_expect reads them.
inline const std::vector<std::string>& expect_figure_names() {
  static const std::vector<std::string> names{
      "momentum_error",   "energy_balance",     "max_depth_over_h", "max_crossings",
      "max_nodes_inside", "max_crossing_depth", "particles_inside"};
  return names;
}

struct ExpectResult {
  std::string name;
  double bound = 0.0;
  double measured = 0.0;  // NaN: not measured (a bound on it fails)
  bool pass = false;
};

/// Each bound against its figure (expect_figure_names). A figure the run did not measure fails
/// its bound.
std::vector<ExpectResult> judge_expect(const std::vector<std::pair<std::string, double>>& bounds,
                                       const ExpectFigures& figures);

}  // namespace tc
