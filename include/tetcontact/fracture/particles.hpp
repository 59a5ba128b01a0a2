// The last stage of fracture (Dobritsa et al., discussion of Fig. 5): destroyed cells on a body's
// boundary turned into discrete particles, and the contacts particles make.
//
// A particle is a free node appended to the state (State::first_particle onward) with the
// radius of the sphere inscribed in its cell: it moves ballistically (no force acts on it),
// and it meets the faces of every body and other particles through the one impulse kernel of
// node–face contact.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "tetcontact/broadphase/binding_lists.hpp"
#include "tetcontact/broadphase/broadphase.hpp"
#include "tetcontact/material/material.hpp"
#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/model/contact_point.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

/// What the conversions moved, summed over the run, and how well each conserved.
struct ConversionLedger {
  long particles = 0;           // cells turned into particles
  double mass = 0.0;            // kg now carried by particles
  double internal = 0.0;        // J: the cells' internal energy, carried by the particles
  double kinetic_spread = 0.0;  // J: ½ Σ_k ¼m|U_k|² − ½ m|Ū|², the kinetic energy of the
                                // cells' spread of nodal velocity, kept as particle energy
  double momentum_error = 0.0;  // largest |Σ_k ¼m U_k − m Ū| / Σ_k ¼m|U_k| of one conversion
  double mass_error = 0.0;      // |Σ nodal mass before − after| / total mass, largest
  long eroded = 0;              // of the particles, cells eroded (their step fell too low, or
                                // their plastic strain reached the material's limit)
};

/// Appends a particle (a free node with that radius, internal energy and cell of origin) to
/// every node array of the state; returns its node index.
Index add_particle(State& st, const Vec3& x, const Vec3& v, double m, double radius, double energy,
                   Index tet);

/// Turns destroyed boundary cells into particles and keeps the surfaces that result.
class Fragmentation {
 public:
  explicit Fragmentation(const Mesh& mesh);

  /// Every destroyed cell with a face on the boundary (at the start of the call: one layer
  /// per step) becomes one particle:
  ///   m = ρ V0 (the four quarters its nodes held, each node losing its quarter),
  ///   Ū = ¼ Σ_k U_k, so that m Ū = Σ_k ¼ m U_k (momentum is exact),
  ///   e = E_cell + ½ Σ_k ¼ m |U_k|² − ½ m |Ū|² (energy is exact),
  /// placed at the centre of the cell's inscribed sphere, r = 3V / Σ A_i. A node left without
  /// cells keeps no mass and no velocity. Returns the number converted; when it is not zero
  /// the caller takes the new surfaces().
  long convert(const Mesh& mesh, const std::vector<Material>& materials, State& st);
  /// Erosion: these cells are turned into particles at the next convert() wherever they are
  /// (an interior one leaves a void whose faces join the surfaces).
  void erode(const std::vector<Index>& tets);

  /// The bodies' surfaces without the converted cells: the faces they exposed are included.
  std::vector<Surface> surfaces(const Mesh& mesh) const;
  const ConversionLedger& ledger() const { return ledger_; }

 private:
  TetNeighbours neighbours_;
  std::vector<char> removed_;       // per tet: turned into a particle
  std::vector<Index> eroding_;      // cells to convert at the next call, wherever they are
  std::vector<int> cells_at_node_;  // remaining cells around each mesh node
  double total_mass_ = 0.0;
  ConversionLedger ledger_;
};

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
