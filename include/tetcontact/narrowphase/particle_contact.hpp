// Contacts of particles (cells turned into free points by fracture) with the faces of every
// body and with each other: the particle narrow phase, on binding lists.
#pragma once

#include <utility>
#include <vector>

#include "tetcontact/broadphase/contact_candidates.hpp"
#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/model/contact_point.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

/// Contacts of particles with the faces of every body and with each other, at tⁿ, for the
/// impulse kernel. A particle–face contact is the centre against the face's closest point:
/// normal from that point to the centre, gap = distance − r (a centre behind a face and
/// inside the face's cell is inside the body: moves() puts it back on the face's plane, and
/// the contact, along the face normal with gap −r, holds it there); particle–particle, gap = |x_i −
/// x_j| − r_i − r_j. Every pair whose swept boxes (inflated by the radius) overlap is a contact
/// with its gap: the kernel lets the particle close at most the gap within the step, so no particle
/// passes through a face whatever its speed (speculative contact).
///
/// The pairs are those the detection's broadphase lists for the particles
/// (broadphase/contact_candidates.hpp, on binding lists): each step a listed pair goes on only
/// when its boxes of the step overlap, so that the contacts, and their order, are those of a fresh
/// search every step (tested).
class ParticleContact {
 public:
  /// `radius_factor`: the particles' radius in the gap to a face, as a fraction of
  /// State::particle_radius (0: the centre; SPH particles that meet the faces through their
  /// kernel touch them by contact only with their centre). `pairs`: the listed particle pairs
  /// are contacts (not for SPH particles, which meet each other through their kernel).
  explicit ParticleContact(double radius_factor = 1.0, bool pairs = true)
      : radius_factor_(radius_factor), pairs_(pairs) {}
  /// The pairs are `candidates.particles()`, updated for this step.
  std::vector<ContactPoint> detect(const Mesh& mesh, const State& st,
                                   const ContactCandidates& candidates);
  /// Of the last detect(): particles found inside a body, with the move (to add to x and x*)
  /// that puts each centre on the plane of the face it is deepest behind.
  const std::vector<std::pair<Index, Vec3>>& moves() const { return moves_; }

 private:
  double radius_factor_;
  bool pairs_;
  std::vector<std::pair<Index, Vec3>> moves_;
  std::vector<Box> step_face_box_;  // this step's boxes of the faces the lists name
};

}  // namespace tc
