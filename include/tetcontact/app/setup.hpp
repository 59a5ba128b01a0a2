// From a validated case to the solver's plain-data model: meshes generated or read,
// transformed, oriented and checked; materials, initial velocities, constraints resolved.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "tetcontact/io/case.hpp"
#include "tetcontact/solver/model.hpp"

namespace tc {

/// Bad input found while building the model (mesh errors, empty regions): exit code 2.
struct SetupError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Builds the model. `notes` receives informational lines (skipped .msh element types, ...).
Model build_model(const Case& c, std::vector<std::string>* notes = nullptr);

SolverSettings solver_settings(const Case& c);

}  // namespace tc
