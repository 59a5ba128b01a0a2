// The solver's state: hot per-node and per-tet arrays, indexed by integers.
#pragma once

#include <cstdint>

#include <vector>

#include "tetcontact/material/material.hpp"
#include "tetcontact/mesh/mesh.hpp"
#include "tetcontact/mesh/surface.hpp"

namespace tc {

/// A cell's failure state (Dobritsa et al.): damaged cells resist only volumetric compression,
/// destroyed ones carry no stress at all, and a destroyed cell on the boundary is turned into a
/// particle (it then leaves the element pass, the surfaces and the output mesh).
enum class Damage : std::uint8_t { intact = 0, damaged = 1, destroyed = 2, particle = 3 };

/// The material of SPH particles (sph/): per particle, what a tet carries of its material's
/// state, updated by the same material-point update (element/material_point.hpp), plus the
/// density and smoothing length of the kernel. Particle i's mass, position and velocity are
/// node first_particle + i's, its internal energy State::particle_energy[i]. Empty where the
/// particles are point masses.
struct ParticleMatter {
  std::vector<double> h;        // smoothing length, m (the kernel reaches 2h)
  std::vector<double> spacing;  // Δp: the particle's own size, V0^(1/3) (artificial stress)
  std::vector<double> rho;      // density, kg/m³
  std::vector<double> vol0;     // reference volume m/ρ0
  std::vector<double> vol;      // current volume m/ρ
  std::vector<Sym6> s;          // deviatoric stress
  std::vector<double> p, q, eps_p, ductile, ductile_floor, w_plastic, w_viscous, sound2, trace_d,
      temperature;  // as the tets' arrays of the same names
  std::vector<Index> material;
  std::vector<Damage> damage;
  // The impulse of this step's kick from the particle's and its neighbours' mirror images
  // across the symmetry planes (the planes' push: momentum from outside the model; its work is
  // the pair work of a particle and its image, internal to the whole).
  std::vector<Vec3> plane_impulse;
  Index size() const { return static_cast<Index>(h.size()); }
};

struct State {
  // Nodes (N).
  std::vector<Vec3> x;             // x^n, current positions
  std::vector<Vec3> v;             // U^n, velocities of the last committed step (t^{n-1/2})
  std::vector<Vec3> v_star;        // U*, predicted then corrected velocities (eq. 2); U^{n+1} after
  std::vector<Vec3> x_star;        // x*, predicted positions (eq. 3)
  std::vector<Vec3> f;             // F^n, internal nodal forces
  std::vector<double> m;           // lumped nodal masses
  std::vector<Vec3> bc_impulse;    // impulse of prescribed velocities this step
  std::vector<Vec3> wall_impulse;  // impulse of rigid walls this step
  std::vector<Vec3> contact_impulse;  // impulse of contacts between bodies this step

  // Tets (M).
  std::vector<double> vol0;           // reference volume
  std::vector<double> vol;            // current volume
  std::vector<Sym6> s;                // deviatoric stress
  std::vector<double> p;              // pressure from the EOS (positive in compression)
  std::vector<double> q;              // artificial bulk viscosity (a pressure, ≥ 0)
  std::vector<double> e_int;          // internal energy, J (elastic + plastic work + viscous heat)
  std::vector<double> eps_p;          // equivalent plastic strain ε̄p
  std::vector<double> ductile;        // Johnson–Cook's ductile damage D (failed at 1)
  std::vector<double> ductile_floor;  // the part of D accrued with ε_f at its floor (the law's
                                      // own ε_f below it: the set outside its fit)
  std::vector<double> w_plastic;      // plastic work, J
  std::vector<double> w_viscous;      // viscous dissipation, J
  std::vector<double> sound2;         // current dilatational sound speed squared, m²/s²
  std::vector<double> trace_d;        // tr D of the last step (volumetric strain rate), 1/s
  std::vector<double> temperature;    // K (materials with a specific heat; else their start value)
  std::vector<Index> tet_material;
  std::vector<Damage> damage;  // per tet

  // Particles (P): destroyed boundary cells turned into free points (Dobritsa et al.), appended
  // after the mesh's nodes, so that the node arrays above carry their mass, velocity and impulses
  // and the one impulse kernel moves them. Particle i is node first_particle + i.
  Index first_particle = 0;  // the mesh's node count
  // A particle is one cell, or with fracture.fragments: clusters several (Fragmentation).
  std::vector<double> particle_radius;  // m: radius of the sphere inscribed in the cell (a
                                        // cluster: of its cells' inscribed spheres' volume)
  std::vector<double> particle_energy;  // J: the cells' internal energy, plus the kinetic
                                        // energy of their nodes' spread of velocity (and of
                                        // the joins of a cluster)
  std::vector<Index> particle_tet;      // the cell each came from (a cluster: its first)
  /// Per particle, bit p: a cluster that holds a cell joined to its own mirror image across
  /// symmetry plane p, i.e. the model's part of one cluster spanning the plane (its mass
  /// counts 2× per such plane in the whole; 0 for every particle of single cells).
  std::vector<unsigned> particle_planes;
  Index particle_count() const { return static_cast<Index>(particle_radius.size()); }
  ParticleMatter sph;  // SPH particles' material (empty: point masses)

  // The surfaces of the run: the model's, less the faces of cells turned into particles, plus
  // the faces those exposed (fracture updates them; everything else reads them).
  std::vector<Surface> surfaces;

  double t = 0.0;        // t^n
  double dt = 0.0;       // τ for the step t^n → t^{n+1}
  double dt_prev = 0.0;  // τ of the previous step
  long step = 0;
};

/// Cauchy stress σ = s − (p + q) I of a tet (the viscosity acts as a pressure).
inline Mat3 cauchy_stress(const State& st, Index t) {
  return to_mat3(st.s[t]) - (st.p[t] + st.q[t]) * Mat3::Identity();
}

}  // namespace tc
