// The resolve stage (contact.verify): the step's motion verified with the exact CCD, and where
// pairs fail, rescue points and further passes; what they leave, a shorter step or, as a last
// resort, rigid impact zones, until none fails.
#pragma once

#include <utility>
#include <vector>

#include "tetcontact/broadphase/contact_candidates.hpp"
#include "tetcontact/model/contact_point.hpp"
#include "tetcontact/model/ledger.hpp"
#include "tetcontact/model/state.hpp"
#include "tetcontact/narrowphase/contact.hpp"
#include "tetcontact/response/impact_zones.hpp"
#include "tetcontact/response/islands.hpp"
#include "tetcontact/verify/verify.hpp"

namespace tc {

/// The contact points of one step, from detection through the passes to the verification
/// (plain data between the stages).
struct StepContacts {
  CandidateStats broadphase;                     // the detection's one broadphase update
  ContactStepStats narrowphase;                  // the narrow phase between bodies
  std::vector<std::vector<ContactPoint>> walls;  // per wall
  std::vector<ContactPoint> bodies;     // between bodies; the verification adds rescue points
  std::vector<ContactPoint> particles;  // particle–face and particle–particle
  std::vector<ContactList> lists;       // the passes' lists over the above, in that order
  std::vector<Index> island_slot;       // contact_islands' scratch
};

class StepResolver {
 public:
  /// Rounds of impact zones a step may take before its failures are reported unresolved
  /// (each round merges, grows or freezes a zone, so a start state free of overlap never
  /// needs this many).
  static constexpr int k_zone_rounds = 64;
  /// Rounds of further passes (`contact.passes` in the first, doubling each round) over the
  /// islands where a step's verification failed, before impact zones.
  static constexpr int k_extra_rounds = 8;

  /// `constraints`: the model's prescribed velocities and symmetry planes, held after every
  /// correction the resolver makes, as after the passes.
  StepResolver(const Mesh& mesh, const std::vector<VelocityConstraint>& constraints);

  /// The surfaces changed (cells turned into particles): the verification's maps over the
  /// primitives are rebuilt.
  void surfaces_changed() { verifier_.surfaces_changed(); }

  /// The step's motion xⁿ → xⁿ⁺¹ = xⁿ + τ U* verified on the detection's lists (`candidates`,
  /// found anew where the end positions leave their reach); failing pairs resolved by rescue
  /// points (from `contact`, added to `points.bodies`), further passes (`passes` in the first
  /// round) and impact zones, which change U* (st.v_star) and may fix end positions
  /// (fixed_positions()). With `may_cut`, pairs still failing after the further passes are left
  /// to the step taken again shorter (Simulation::step) instead of zones where a halving may
  /// help them (helped_by_cut): returns false then. The counts go to `ledger`.
  bool resolve(State& st, StepContacts& points, ContactCandidates& candidates,
               const ContactDetection& contact, int passes, bool may_cut, ContactLedger& ledger);

  /// Nodes of translated and frozen impact zones of the last resolve() with their xⁿ⁺¹: the
  /// commit writes these positions.
  const std::vector<std::pair<Index, Vec3>>& fixed_positions() const { return fixed_x_; }

 private:
  Verification verify_again(const State& st, ContactCandidates& candidates, ContactLedger& ct);
  void end_positions(const State& st);
  Verification extra_passes(State& st, StepContacts& points, ContactCandidates& candidates,
                            const ContactDetection& contact, int passes, Verification v,
                            ContactLedger& ct);
  bool helped_by_cut(const State& st, const Verification& v);
  Verification impact_zones(State& st, StepContacts& points, ContactCandidates& candidates,
                            int passes, Verification v, ContactLedger& ct);
  // The constraints held, as hold_constraints() does after the passes (their impulse booked as
  // the boundary's); `impulses`, when given, receives each held node's impulse.
  void hold(State& st, std::vector<Vec3>* impulses);

  StepVerifier verifier_;
  // Per node, the components a constraint prescribes (bit d) and their velocity.
  std::vector<unsigned char> held_;
  std::vector<Vec3> held_velocity_;
  std::vector<Index> held_nodes_;  // the nodes with a prescribed component, ascending
  std::vector<Vec3> zone_hold_;    // per held node, the constraints' impulse of the zone round
  // Working arrays, kept between steps to save allocations.
  std::vector<Vec3> x_end_;  // xⁿ⁺¹ as the commit will write it
  ImpactZones zones_;
  std::vector<Vec3> u_passes_;        // U* as the passes left it (zone steps)
  std::vector<char> marked_;          // nodes of failing pairs
  std::vector<char> in_rigid_;        // nodes in rigid zones
  std::vector<ContactPoint> inside_;  // the contact points inside rigid zones, from Λ = 0
  std::vector<Index> changed_;  // nodes whose end position changed since the last verification
  std::vector<Vec3> x_tested_;  // the end positions last verified
  std::vector<std::pair<Index, Vec3>> fixed_x_;  // nodes of translated and frozen zones, xⁿ⁺¹
  // The pairs (edge–edge, nodes) the last try left to a shorter step, sorted, and its step.
  std::vector<std::array<Index, 5>> cut_failing_;
  long cut_at_step_ = -1;
  long failed_at_step_ = -1;  // the last step with failing pairs (ContactLedger::steps_failed)
};

}  // namespace tc
