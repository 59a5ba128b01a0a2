// A case's stated bounds (`expect:`), judged against the figures of a run: one code path for
// `run --check` and the micro-scenes of `stress`.
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

struct ExpectResult {
  std::string name;
  double bound = 0.0;
  double measured = 0.0;  // NaN: not measured (a bound on it fails)
  bool pass = false;
};

/// Each bound against its figure: momentum_error, energy_balance, max_depth_over_h,
/// max_crossings, max_nodes_inside, max_crossing_depth, particles_inside. A figure the run did
/// not measure fails its bound.
std::vector<ExpectResult> judge_expect(const std::vector<std::pair<std::string, double>>& bounds,
                                       const ExpectFigures& figures);

}  // namespace tc
