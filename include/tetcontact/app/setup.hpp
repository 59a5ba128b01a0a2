// From a validated case to the solver's plain-data model: meshes generated or read,
// transformed, oriented and checked; materials, initial velocities, constraints resolved.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "tetcontact/io/case.hpp"
#include "tetcontact/model/model.hpp"

namespace tc {

/// Bad input found while building the model (mesh errors, empty regions): exit code 2.
struct SetupError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Builds the model. `notes` receives informational lines (skipped .msh element types, ...).
Model build_model(const Case& c, std::vector<std::string>* notes = nullptr);

SolverSettings solver_settings(const Case& c);

/// Bodies that overlap at t = 0 (a boundary node strictly inside another body, a boundary edge
/// through another's face; exact, touching allowed) throw SetupError naming the bodies and the
/// depth. build_model calls it unless the case sets contact.initial_overlap: allow.
void check_initial_overlap(const Case& c, const Model& model);

/// Impact Mach numbers M0 = U0 / C0 outside the range of the model a body uses (Dobritsa et al.:
/// elastic-plastic flow with a linear EOS for M0 ≤ 0.75, a hydrodynamic model with a richer
/// EOS for 0.75 < M0 < 1.5). U0 is the closing speed of each pair of bodies (difference of
/// their mass-averaged initial velocities) and of each body against each wall; C0 is the
/// body's bulk sound speed. One line per finding.
std::vector<std::string> mach_warnings(const Case& c, const Model& model);

/// The regime each impact is in where it is inside the paper's models but past the
/// elastic-plastic one: 0.75 < M0 < 1.5 with a Mie–Grüneisen EOS (a run states the
/// regime it is in, and what the model leaves out there). Not warnings: statements.
std::vector<std::string> regime_notes(const Case& c, const Model& model);

}  // namespace tc
