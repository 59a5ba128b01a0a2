// Contacts of particles (cells turned into free points by fracture) with the faces of every
// body and with each other: the particle narrow phase, on binding lists.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tetcontact/broadphase/binding_lists.hpp"
#include "tetcontact/broadphase/broadphase.hpp"
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
/// Binding lists (broadphase/binding_lists.hpp, as for contact between bodies): the broadphase
/// runs with every box enlarged by the reach (binding_reach of the surfaces) and its pairs are
/// kept until a particle or a surface node has moved that far from where it was then, or
/// reset() is called (particles added, surfaces rebuilt). Each step a kept pair goes on only when
/// its boxes of the step overlap: the contacts, and their order, are those of a fresh broadphase
/// every step (tested).
class ParticleContact {
 public:
  explicit ParticleContact(const std::string& broadphase, bool binding_lists = true);
  std::vector<ContactPoint> detect(const std::vector<Surface>& surfaces, const Mesh& mesh,
                                   const State& st);
  /// Of the last detect(): particles found inside a body, with the move (to add to x and x*)
  /// that puts each centre on the plane of the face it is deepest behind.
  const std::vector<std::pair<Index, Vec3>>& moves() const { return moves_; }
  /// The particles or the surfaces changed: the next detect() builds new lists.
  void reset() { lists_.reset(); }
  /// Broadphase runs so far (each a rebuild of the lists).
  long broadphase_runs() const { return runs_; }

 private:
  bool lists_valid(const std::vector<Surface>& surfaces, const State& st) const;
  void build_lists(const std::vector<Surface>& surfaces, const State& st);
  std::unique_ptr<Broadphase> broadphase_;
  bool binding_lists_ = true;
  std::vector<std::pair<Index, Vec3>> moves_;
  // The lists: (particle, face) with faces numbered over all surfaces in order (node_face),
  // and particle pairs (edge_edge); the points they hold for: every particle, then every
  // surface node.
  BindingLists lists_;
  long runs_ = 0;
  Index particles_listed_ = 0;
  std::vector<Index> anchored_;
  std::vector<std::pair<Index, Index>> face_at_;  // (surface, face) of each face number
  // This step's boxes of the faces the lists name.
  std::vector<Index> listed_faces_;
  std::vector<Box> step_face_box_;
};

}  // namespace tc
