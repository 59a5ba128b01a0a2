// The last stage of fracture (Dobritsa et al., discussion of Fig. 5): destroyed cells on a body's
// boundary turned into discrete particles (their contacts are detected in
// narrowphase/particle_contact.hpp).
//
// A particle is a free node appended to the state (State::first_particle onward) with the
// radius of the sphere inscribed in its cell: it moves ballistically (no force acts on it),
// and it meets the faces of every body and other particles through the one impulse kernel of
// node–face contact. With fragments as clusters a converted cell may instead join the particle
// of a neighbouring cell that moves with it, so that a fragment of several cells strikes as one.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "tetcontact/material/material.hpp"
#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/model/state.hpp"
#include "tetcontact/sph/sph.hpp"

namespace tc {

class Archive;

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
  long joined = 0;              // of the cells converted, those that joined a cluster
  double cohesion_loss = 0.0;  // J: ½ M m/(M+m) |V − Ū|² of the joins, kept as particle energy
};

/// What a converted cell becomes: a particle of its own, or part of a neighbour's cluster.
enum class Fragments {
  cells,     // each cell its own particle (the default)
  clusters,  // a cell joins the particle of a face neighbour that moves with it (cohesion)
};

/// The speed below which two pieces of a material still cohere: v_c = 2 σ* / (ρ0 c0), at which
/// they load the plane between them to their spall strength σ* (0 without one).
double cohesion_speed(const Material& m);

/// Appends a particle (a free node with that radius, internal energy and cell of origin) to
/// every node array of the state; returns its node index.
Index add_particle(State& st, const Vec3& x, const Vec3& v, double m, double radius, double energy,
                   Index tet);

/// Turns destroyed boundary cells into particles and keeps the surfaces that result.
class Fragmentation {
 public:
  /// sph_smoothing > 0: the particles are SPH particles (sph/) that keep their cell's material
  /// and state (sph::append_cell_matter), h = sph_smoothing × the cell's V0^(1/3); 0: point
  /// masses.
  explicit Fragmentation(const Mesh& mesh, Fragments fragments = Fragments::cells,
                         double sph_smoothing = 0.0);

  /// Every destroyed cell with a face on the boundary (at the start of the call: one layer
  /// per step) becomes one particle:
  ///   m = ρ V0 (the four quarters its nodes held, each node losing its quarter),
  ///   Ū = ¼ Σ_k U_k, so that m Ū = Σ_k ¼ m U_k (momentum is exact),
  ///   e = E_cell + ½ Σ_k ¼ m |U_k|² − ½ m |Ū|² (energy is exact),
  /// placed at the centre of the cell's inscribed sphere, r = 3V / Σ A_i. A node left without
  /// cells keeps no mass and no velocity. Returns the number converted; when it is not zero
  /// the caller brings the surfaces up to date with update().
  ///
  /// With Fragments::clusters a cell joins, instead, the particle P (mass M, velocity V) that
  /// holds a face neighbour of the same material when the two still cohere: their relative
  /// speed is below the speed at which a tension of the spall strength σ* parts them,
  ///   |V − Ū| < v_c = 2 σ* / (ρ0 c0)   (two halves parting at v_c load the plane between them
  ///                                      to ρ0 c0 v_c / 2 = σ*),
  /// and the cell's centre lies within 2 (R + r) of P's. The join is a perfectly inelastic
  /// collision: mass M + m, momentum M V + m Ū, position the centre of mass, energy
  /// E_P + e + ½ M m/(M+m) |V − Ū|², radius that of the sphere of the members' inscribed
  /// spheres' volume, R = (Σ r_k³)^(1/3). Of several such neighbours the slowest relative one
  /// (then the lowest node) is taken; the cells are visited in increasing index, so a run is
  /// repeatable. A material without spall strength does not cohere. On a symmetry plane a
  /// cell coheres with its own mirror image when 2 |Ū·n| < v_c: its particle is then the
  /// model's part of a cluster spanning the plane (State::particle_planes).
  long convert(const Mesh& mesh, const std::vector<Material>& materials, State& st);
  /// Erosion: these cells are turned into particles at the next convert() wherever they are
  /// (an interior one leaves a void whose faces join the surfaces).
  void erode(const std::vector<Index>& tets);

  /// `surfaces` made the bodies' surfaces without the converted cells (the faces they exposed
  /// included): built whole at the first call (and the first after a checkpoint is read), then
  /// updated in place for the cells converted since the last call (update_surfaces: the same
  /// surfaces, without reading every cell). Between calls nothing else may change them.
  void update(const Mesh& mesh, std::vector<Surface>& surfaces);
  const ConversionLedger& ledger() const { return ledger_; }
  /// The node of the particle that holds this cell, or −1 while it is a cell.
  Index particle_of(Index tet) const { return particle_of_[tet]; }
  /// What a checkpoint holds of it (model/archive.hpp): the converted cells, the cells to
  /// convert, the particles holding them, the ledger.
  void persist(Archive& ar);

 private:
  Index cohering(Index t, const State& st, const std::vector<Material>& materials,
                 const Vec3& centre, const Vec3& u, double radius) const;
  unsigned spanned_planes(Index t, const Mesh& mesh, const Material& mat, const Vec3& u) const;
  void join(State& st, Index p, const Vec3& centre, const Vec3& u, double m, double radius,
            double energy);

  TetNeighbours neighbours_;
  std::vector<EdgeLengths> lengths_;  // the bodies' tet edge lengths (the surfaces')
  std::vector<char> removed_;         // per tet: turned into a particle
  std::vector<Index> gone_;           // the cells converted since the last update()
  bool surfaces_built_ = false;       // update() has built the surfaces it is given
  std::vector<Index> eroding_;        // cells to convert at the next call, wherever they are
  std::vector<int> cells_at_node_;    // remaining cells around each mesh node
  Fragments fragments_ = Fragments::cells;
  double sph_smoothing_ = 0.0;           // > 0: SPH particles
  std::vector<Index> particle_of_;       // per tet: the node of the particle holding it, or −1
  std::vector<unsigned> mirror_planes_;  // per tet (clusters with symmetry planes): the planes
                                         // its faces lie on
  double total_mass_ = 0.0;
  ConversionLedger ledger_;
};

}  // namespace tc
