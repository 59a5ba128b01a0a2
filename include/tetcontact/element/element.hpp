// Constant-strain linear tetrahedra: material update, internal forces, stable time step.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "tetcontact/model/model.hpp"
#include "tetcontact/model/state.hpp"
#include "tetcontact/parallel/lanes.hpp"

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
/// face area); they sum to zero. ∇N_i = −a_i / (3V). Faces opposite nodes 0..3 with outward
/// orientation: (1,2,3), (0,3,2), (0,1,3), (0,2,1).
[[gnu::always_inline]] inline std::array<Vec3, 4> face_area_vectors(const Vec3& x0, const Vec3& x1,
                                                                    const Vec3& x2,
                                                                    const Vec3& x3) {
  const Vec3 e1 = x1 - x0, e2 = x2 - x0, e3 = x3 - x0;
  std::array<Vec3, 4> a;
  a[1] = 0.5 * e3.cross(e2);
  a[2] = 0.5 * e1.cross(e3);
  a[3] = 0.5 * e2.cross(e1);
  a[0] = -(a[1] + a[2] + a[3]);
  return a;
}

/// The kernel's working arrays, sized on first use. Each tet writes only its own entries
/// (its four corner forces, its shares of the nodal averages); the nodes then gather them over
/// the node–tet incidence in ascending tet order, which is the order a serial scatter adds
/// them in: the same sums, bit for bit, on any number of threads.
struct ElementScratch {
  // Node → (tet, corner) incidence: entries 4t + corner of node a in
  // incidence[incidence_begin[a] .. incidence_begin[a + 1]), ascending in t.
  std::vector<Index> incidence_begin, incidence;
  std::vector<Vec3> tet_force;  // per tet corner (4 per tet): its share of the nodal force
  // Average nodal pressure.
  std::vector<double> vol0, pressure, node_j;  // per node (node_j: volume ratio V / V0)
  std::vector<Index> node_material;            // per node: material if averaged, else −1
  std::vector<double> tet_dvol;                // per tet: ΔV of the step
  std::vector<double> tet_energy;              // per tet: Eⁿ, its share of the nodal energy
  std::vector<char> tet_averaged;              // per tet: in the nodal averages this step
  // Distributed runs: every rank's tets, ascending, and this process's rank. Each
  // process updates its own tets, and every process then receives what the whole step needs
  // of the others' (element.cpp): the nodal forces, and per tet the energies and damage of the
  // balance. Empty: one process, all the tets.
  std::vector<std::vector<Index>> rank_tets;
  int rank = 0;
  // Built from rank_tets once: per rank, the nodes all of whose tets it owns (it sums their
  // forces and sends the sums), the corners of its tets at nodes shared with another rank
  // (sent as they are, and every rank sums those nodes in tet order, as one process does),
  // and its tets with a shared node (their inputs to the nodal averages are sent); the
  // shared nodes; the nodes of this process's tets (the nodal averages it needs), ascending.
  std::vector<std::vector<Index>> rank_nodes, rank_shared_corners, rank_frontier_tets;
  std::vector<Index> shared_nodes, my_nodes;
};

struct ForceResult {
  double dt_stable = 0.0;      // min over tets of the viscous CFL limit
  Index critical_tet = -1;     // the tet that sets it
  std::vector<Index> eroding;  // tets whose stable step fell below the erosion limit
};

/// A distributed run (scratch.rank_tets set): every per-tet field gathered from the rank that
/// owns the tet, so that every process holds the whole state (before a frame, at the end).
/// Collective; nothing on one process.
void share_whole_state(ElementScratch& scratch, State& st);

/// Internal nodal forces F at the current positions from σ = s − (p + q) I, and the stable
/// time step. For a constant-strain tet the force on node i is
///   f_i = −V σ ∇N_i = σ a_i / 3,
/// and the CFL limit of a tet with smallest altitude l = 3V / max|a_i|, sound speed c and
/// viscosity Q = C1 c + C2 l |ε̇v| (compression) is l / (Q + sqrt(Q² + c²)).
/// Throws InvertedElement for a tet with V ≤ 0.
ForceResult compute_forces(const std::vector<Tet>& tets, const ElementOptions& options, State& st,
                           ElementScratch& scratch);

/// How the element stage runs the cells' kinematics and material update and the averaged
/// pressure's pass (parallel/lanes.hpp): one cell at a time (`Lanes::scalar`, the reference), or
/// eight cells a block in SIMD lanes. Sets it; returns the previous setting. Lanes wider than
/// widest_lanes() throw std::invalid_argument.
Lanes set_element_lanes(Lanes lanes);

/// Material update over the step from the committed velocities U^{n+1} (st.v):
///   L = Σ_i U_i ⊗ ∇N_i at the mid-step geometry x^{n+1/2} = x^{n+1} − τ/2 U^{n+1};
///   deviator by update_deviator (Jaumann rate, radial return);
///   pressure by the EOS at μ = V0/V^{n+1} − 1 — per tet, or with average nodal pressure
///   (Bonet & Burton 1998) averaged from nodal pressures p_a = p(V0_a/V_a − 1, E_a) with the
///   nodal volumes V_a = Σ V/4 of the tets around node a;
///   viscosity q by bulk_viscosity;
///   internal energy by the trapezoidal work
///     ΔE = τ V ½(s^n + s^{n+1}) : D − ½ (p^n + p^{n+1}) ΔV − ½ (q^n + q^{n+1}) ΔV,
///   solved exactly for E^{n+1} when p depends on E (Mie–Grüneisen, per-tet pressure).
/// For small-strain linear elasticity ΔE equals the stored energy ½ ε:C:ε.
/// Then, in the same pass over the tets, the internal forces and stable step of the new state
/// (as compute_forces, which the tests hold it to).
ForceResult update_material(const std::vector<Tet>& tets, const std::vector<Material>& materials,
                            const ElementOptions& options, double tau, State& st,
                            ElementScratch& scratch);

/// Sets the per-tet sound speed from the current state (needed before the first forces).
void init_sound_speed(const std::vector<Material>& materials, State& st);

/// Each body's stable step at the current state: the smallest over its cells (particles
/// skipped) of the step compute_forces takes; infinite for a body without cells. Every tet's
/// fields are read (on every rank: at the first step they are the setup's).
std::vector<double> body_stable_steps(const std::vector<Tet>& tets,
                                      const std::vector<Index>& tet_body, std::size_t bodies,
                                      const ElementOptions& options, const State& st);

/// The element stage of a run: the model's element options (with the erosion limit the first
/// step sets) and the arrays it keeps between steps (ElementScratch), over the mesh's tets.
class ElementStage {
 public:
  explicit ElementStage(const ElementOptions& options) : options_(options) {}
  /// Distributed: this process is `rank` and updates the tets rank_tets[rank] (each ascending).
  void distribute(int rank, std::vector<std::vector<Index>> rank_tets) {
    scratch_.rank = rank;
    scratch_.rank_tets = std::move(rank_tets);
  }
  /// This rank's tets; null on one process.
  const std::vector<Index>* rank_tets() const {
    return scratch_.rank_tets.empty() ? nullptr : &scratch_.rank_tets[scratch_.rank];
  }
  /// A cell of body b whose stable step squared falls below dt2[b] is listed eroding (empty:
  /// none); tet_body is the mesh's, which outlives the stage.
  void set_erosion_limits(std::vector<double> dt2, std::span<const Index> tet_body) {
    options_.erode_dt2 = std::move(dt2);
    options_.tet_body = tet_body;
  }
  const std::vector<double>& erosion_limits() const { return options_.erode_dt2; }
  /// The forces and stable step of the current state (compute_forces).
  ForceResult forces(const std::vector<Tet>& tets, State& st) {
    return compute_forces(tets, options_, st, scratch_);
  }
  /// The step's material update, forces and stable step (update_material).
  ForceResult update(const std::vector<Tet>& tets, const std::vector<Material>& materials,
                     double tau, State& st) {
    return update_material(tets, materials, options_, tau, st, scratch_);
  }
  /// Distributed: every tet's fields on every rank (share_whole_state); nothing on one process.
  void share_whole_state(State& st) { tc::share_whole_state(scratch_, st); }

 private:
  ElementOptions options_;
  ElementScratch scratch_;
};

}  // namespace tc
