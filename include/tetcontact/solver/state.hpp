// The solver's state: hot per-node and per-tet arrays, indexed by integers.
#pragma once

#include <vector>

#include "tetcontact/material/elastic.hpp"
#include "tetcontact/mesh/mesh.hpp"

namespace tc {

struct State {
  // Nodes (N).
  std::vector<Vec3> x;           // x^n, current positions
  std::vector<Vec3> v;           // U^n, velocities of the last committed step (t^{n-1/2})
  std::vector<Vec3> v_star;      // U*, predicted then corrected velocities (eq. 2); U^{n+1} after
  std::vector<Vec3> x_star;      // x*, predicted positions (eq. 3)
  std::vector<Vec3> f;           // F^n, internal nodal forces
  std::vector<double> m;         // lumped nodal masses
  std::vector<Vec3> bc_impulse;  // reaction impulse of prescribed velocities this step

  // Tets (M).
  std::vector<double> vol0;   // reference volume
  std::vector<double> vol;    // current volume
  std::vector<Sym6> s;        // deviatoric stress
  std::vector<double> p;      // pressure (positive in compression)
  std::vector<double> e_int;  // internal energy, J (per tet, not per unit mass)
  std::vector<Index> tet_material;

  double t = 0.0;        // t^n
  double dt = 0.0;       // τ for the step t^n → t^{n+1}
  double dt_prev = 0.0;  // τ of the previous step
  long step = 0;
};

/// Cauchy stress σ = s − p I of a tet.
inline Mat3 cauchy_stress(const State& st, Index t) {
  return to_mat3(st.s[t]) - st.p[t] * Mat3::Identity();
}

}  // namespace tc
