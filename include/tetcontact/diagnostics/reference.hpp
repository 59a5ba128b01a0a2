// Reference values a case declares (`reference:` in the case file) and their measurement
// from a run: the validation cases carry their published or analytical numbers with them.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "tetcontact/solver/model.hpp"
#include "tetcontact/solver/state.hpp"

namespace tc {

struct ReferenceSpec {
  enum class Measure {
    length,        // extent of a body's bounding box along `axis`
    radius,        // half the largest bounding-box extent across `axis`
    mean_stress,   // mean over the tets centred in `region` of −σ_component (compression > 0)
    mean_pressure  // mean over the tets centred in `region` of the EOS pressure p
  };
  std::string name;  // shown in tables
  Measure measure = Measure::length;
  std::string body;   // length, radius
  int axis = 2;       // 0, 1, 2 for x, y, z
  int component = 2;  // mean_stress: 0..5 in the order xx yy zz xy yz xz
  Vec3 region_min = Vec3::Zero(), region_max = Vec3::Zero();  // mean_stress, mean_pressure
  double value = 0.0;                                         // the reference
  double tolerance = 0.0;                                     // allowed relative error
  std::string source;                                         // where the reference comes from
};

struct ReferenceResult {
  const ReferenceSpec* spec = nullptr;
  double measured = 0.0;
  double relative_error = 0.0;  // (measured − value) / |value|
  bool pass = false;
};

/// Measures each reference on the final state. Throws std::runtime_error when a measure has
/// nothing to measure (unknown body, empty region).
std::vector<ReferenceResult> evaluate_references(const std::vector<ReferenceSpec>& refs,
                                                 const Model& model, const State& st);

}  // namespace tc
