#include <algorithm>

#include "tetcontact/model/model.hpp"
#include "tetcontact/model/sample.hpp"

namespace tc {

double& StepProfile::operator[](Stage stage) {
  const std::string_view name = name_of(k_stage_names, stage);  // no string made per lookup
  for (auto& [n, s] : stages)
    if (n == name) return s;
  stages.emplace_back(std::string(name), 0.0);
  return stages.back().second;
}

double StepProfile::total() const {
  double t = 0.0;
  for (const auto& s : stages) t += s.second;
  return t;
}

std::vector<Index> all_surface_nodes(const std::vector<Surface>& surfaces) {
  std::vector<Index> nodes;
  for (const Surface& s : surfaces) nodes.insert(nodes.end(), s.nodes.begin(), s.nodes.end());
  std::sort(nodes.begin(), nodes.end());
  return nodes;
}

}  // namespace tc
