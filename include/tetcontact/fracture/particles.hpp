// The last stage of fracture (Dobritsa et al., discussion of Fig. 5): destroyed cells on a body's
// boundary turned into discrete particles (their contacts are detected in
// narrowphase/particle_contact.hpp).
//
// A particle is a free node appended to the state (State::first_particle onward) with the
// radius of the sphere inscribed in its cell: it moves ballistically (no force acts on it),
// and it meets the faces of every body and other particles through the one impulse kernel of
// node–face contact.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "tetcontact/material/material.hpp"
#include "tetcontact/mesh/surface.hpp"
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
  std::vector<EdgeLengths> lengths_;  // the bodies' tet edge lengths (the surfaces')
  std::vector<char> removed_;         // per tet: turned into a particle
  std::vector<Index> eroding_;        // cells to convert at the next call, wherever they are
  std::vector<int> cells_at_node_;    // remaining cells around each mesh node
  double total_mass_ = 0.0;
  ConversionLedger ledger_;
};

}  // namespace tc
