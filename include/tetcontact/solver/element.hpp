// Constant-strain linear tetrahedra: internal forces, stable time step, stress update.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "tetcontact/solver/state.hpp"

namespace tc {

/// The run cannot go on (non-finite values, an inverted element): exit code 1.
struct RunFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// An element turned inside out (or collapsed) during the run.
struct InvertedElement : RunFailure {
  Index tet;
  InvertedElement(Index t, const std::string& what) : RunFailure(what), tet(t) {}
};

/// Outward area vectors a_i of the faces opposite each node of a positive tet (|a_i| is the
/// face area); they sum to zero. ∇N_i = −a_i / (3V).
std::array<Vec3, 4> face_area_vectors(const Vec3& x0, const Vec3& x1, const Vec3& x2,
                                      const Vec3& x3);

struct ForceResult {
  double dt_stable = 0.0;   // min over tets of (min altitude / wave speed)
  Index critical_tet = -1;  // the tet that sets it
};

/// Internal nodal forces F at the current positions from the current stress, and the stable
/// time step. For a constant-strain tet the force on node i is
///   f_i = −V σ ∇N_i = σ a_i / 3,
/// and the CFL limit uses the smallest altitude h = 3V / max|a_i| and the material's
/// dilatational wave speed. Throws InvertedElement for a tet with V ≤ 0.
ForceResult compute_forces(const std::vector<Tet>& tets, const std::vector<Material>& materials,
                           State& st);

/// Stress update over the step from the committed velocities U^{n+1} (st.v), with the velocity
/// gradient L = Σ_i U_i ⊗ ∇N_i taken at the mid-step geometry x^{n+1/2} = x^{n+1} − τ/2 U^{n+1}.
/// Internal energy grows by the trapezoidal work τ V (σ^n + σ^{n+1})/2 : D, which equals the
/// exact stored energy ½ ε:C:ε of small-strain linear elasticity.
void update_stress(const std::vector<Tet>& tets, const std::vector<Material>& materials, double tau,
                   State& st);

}  // namespace tc
