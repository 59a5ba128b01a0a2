// What a time level reports, as plain data (the data layer): the balance sample at t^n, the
// observer interface through which output and diagnostics see each time level, and the
// seconds per stage.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "tetcontact/model/names.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

/// Work and impulse of one kind of external impulse (prescribed velocities, walls),
/// accumulated between samples in the leapfrog's bookkeeping (see sample_balance).
struct ImpulseLedger {
  double work = 0.0;                  // to t^n, J
  Vec3 impulse = Vec3::Zero();        // to t^n, N s
  double work_ahead = 0.0;            // the share of this step's impulses due at t^{n+1}
  Vec3 impulse_ahead = Vec3::Zero();  // likewise for the impulse
};

/// Balance at t^n, sampled after the prediction (and corrections) of step n, when both U^n
/// and U^{n+1} are known.
struct Sample {
  long step = 0;
  double t = 0.0;
  double dt = 0.0;
  double kinetic = 0.0;        // ½ Σ m U^n·(U^n + τ^{n-1/2} a^n)  (see below)
  double internal = 0.0;       // Σ e_int over tets (elastic + plastic work + viscous heat)
                               // and the energy particles carry
  double plastic_work = 0.0;   // part of internal
  double viscous_work = 0.0;   // part of internal
  ImpulseLedger boundary;      // prescribed velocities: work and impulse to t^n
  ImpulseLedger walls;         // rigid walls: work and impulse to t^n
  ImpulseLedger contact;       // contacts between bodies: work (≤ 0) and impulse (≈ 0) to t^n
  ImpulseLedger planes;        // symmetry planes on SPH particles (their images): impulse to
                               // t^n (its work is internal: a particle's pair work with its
                               // image, which the whole books as the pair's heat)
  double contact_heat = 0.0;   // the heat the exchanges (and the symmetry planes') deposited
                               // in cells and particles before t^n (response/heat.hpp;
                               // part of internal)
  double contact_force = 0.0;  // total normal contact force this step (Σ λ / τ), N
  long contacts = 0;           // node–face contacts this step
  long damaged = 0;            // cells spalled (damaged, not destroyed) at t^n
  long destroyed = 0;          // cells destroyed (loosened) at t^n
  long particles = 0;          // particles so far (a cluster of cells counts once)
  double particle_mass = 0.0;  // kg carried by particles (part of mass)
  double total = 0.0;          // kinetic + internal
  double balance_error = 0.0;  // filled by the Simulation (see balance_error_max)
  double mass = 0.0;
  Vec3 momentum = Vec3::Zero();    // Σ m (U^n + U^{n+1}) / 2
  double momentum_scale = 0.0;     // Σ m |U^n + U^{n+1}| / 2, for relative errors
  std::vector<double> wall_force;  // normal reaction force on each wall this step, N
  bool final = false;              // the run's last sample (Simulation::finish)

  /// Work done on the bodies by everything outside them (boundary conditions, walls).
  double external_work() const { return boundary.work + walls.work; }
  Vec3 external_impulse() const { return boundary.impulse + walls.impulse + planes.impulse; }
};

/// The stages of a step, in pipeline order (Simulation::step), each timed into the profile.
enum class Stage {
  predict,      // U*, x*
  broadphase,   // detect: candidate pairs (binding lists)
  narrowphase,  // detect: node–face and edge–edge contact points
  particles,    // detect: particle contact points
  response,     // respond: the sequential passes over walls and contacts, by islands
  verify,       // resolve: the step verified, rescue points, impact zones (contact.verify; a
                // step taken again shorter counts its stages again, each where it belongs)
  balance,      // sample: energy and momentum at tⁿ
  output,       // observers see tⁿ
  commit,       // Uⁿ⁺¹, xⁿ⁺¹
  fracture,     // destroyed boundary cells → particles
  elements,     // σⁿ⁺¹, Fⁿ⁺¹, the next step
  sph,          // SPH particles: σⁿ⁺¹, Fⁿ⁺¹, their stable step (fracture.debris: sph)
};
inline constexpr NameTable<Stage, 12> k_stage_names{{{Stage::predict, "predict"},
                                                     {Stage::broadphase, "broadphase"},
                                                     {Stage::narrowphase, "narrowphase"},
                                                     {Stage::particles, "particles"},
                                                     {Stage::response, "response"},
                                                     {Stage::verify, "verify"},
                                                     {Stage::balance, "balance"},
                                                     {Stage::output, "output"},
                                                     {Stage::commit, "commit"},
                                                     {Stage::fracture, "fracture"},
                                                     {Stage::elements, "elements"},
                                                     {Stage::sph, "sph"}}};

/// Seconds spent in each stage over the run, in pipeline order: the stages the case uses
/// (history.csv's seconds_* columns and summary.timings, by their names).
struct StepProfile {
  std::vector<std::pair<std::string, double>> stages;
  /// The stage's seconds (listed, after those listed before, on first use).
  double& operator[](Stage stage);
  double total() const;
};

/// A stage that looks at the complete state at t^n (positions, stresses, U^n and U^{n+1})
/// once per step: output writers, diagnostics.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void observe(const State& st, const Sample& sample) = 0;
};

}  // namespace tc
