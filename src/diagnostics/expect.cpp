#include "tetcontact/diagnostics/expect.hpp"

#include <cmath>
#include <limits>

namespace tc {

std::vector<ExpectResult> judge_expect(const std::vector<std::pair<std::string, double>>& bounds,
                                       const ExpectFigures& f) {
  std::vector<ExpectResult> out;
  for (const auto& [name, bound] : bounds) {
    double v = std::numeric_limits<double>::quiet_NaN();
    const Penetration* p = f.penetration ? &*f.penetration : nullptr;
    if (name == "momentum_error") v = f.momentum_error;
    if (name == "energy_balance") v = f.energy_balance;
    if (name == "max_depth_over_h" && p) v = p->max_depth_over_h;
    if (name == "max_crossings" && p) v = static_cast<double>(p->crossings);
    if (name == "max_nodes_inside" && p) v = static_cast<double>(p->nodes_inside);
    if (name == "max_crossing_depth" && p) v = p->max_crossing_depth;
    if (name == "particles_inside" && f.particles_inside_end)
      v = static_cast<double>(*f.particles_inside_end);
    out.push_back({name, bound, v, v <= bound});  // NaN (not measured) fails
  }
  return out;
}

}  // namespace tc
