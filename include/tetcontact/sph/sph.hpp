// Solid SPH for debris: particles that are material (Libersky and Petschek's formulation, with
// Monaghan's viscosity and artificial stress). Each particle carries mass, density, volume,
// velocity, deviatoric stress, internal energy, temperature, plastic strain and damage
// (State::sph, ParticleMatter); its material law is the tets' own, through the one
// material-point update (element/material_point.hpp).
//
// With ∇_i W_ij = ∇_i W(|x_i − x_j|, h_ij), h_ij = ½ (h_i + h_j), v_ij = v_i − v_j,
// σ = s − p I the Cauchy stress (tension > 0):
//
//   velocity gradient   L_i = −(1/ρ_i) Σ_j m_j v_ij ⊗ ∇_i W_ij           (∂v^a/∂x^b)
//   continuity          dρ_i/dt = Σ_j m_j v_ij · ∇_i W_ij = −ρ_i tr L_i
//   momentum            dv_i/dt = Σ_j m_j (σ_i/ρ_i² + σ_j/ρ_j² + A_ij) ∇_i W_ij,
//                       A_ij = −Π_ij I + f_ijⁿ (R_i + R_j)
//   energy              de_i/dt = σ_i : D_i / ρ_i − ½ Σ_j m_j v_ij · A_ij ∇_i W_ij
//
// Π_ij is Monaghan's viscosity, (−α c̄ μ_ij + β μ_ij²) / ρ̄ with μ_ij = h_ij v_ij·x_ij /
// (|x_ij|² + 0.01 h_ij²) when the pair approaches (0 otherwise); R_i Monaghan's artificial
// stress against the tensile instability (J. J. Monaghan, J. Comput. Phys. 159, 290, 2000;
// J. P. Gray, J. J. Monaghan, R. P. Swift, Comput. Methods Appl. Mech. Eng. 190, 6641, 2001):
// in the principal frame of σ_i, R'_aa = −ε σ'_aa / ρ_i² where σ'_aa > 0 (tension), else 0,
// and f_ij = W(|x_ij|, h_ij) / W(Δp, h_ij) with Δp the mean particle spacing. The pair terms
// are equal and opposite to the bit, so momentum is kept to the round-off of the sums; the
// energy's pair term is the work of A_ij, so the total energy is kept but for the integrator's
// O(τ²).
//
// The step (the engine's: velocities at half steps, positions at whole ones):
//   update: from U^{n+1/2} at the mid-step positions x^{n+1} − τ/2 U: L_i, then the material
//           point's update (deviator, equation of state, temperature, failure) with the volume
//           solved from dV/dt = V tr D by the trapezoid, Vⁿ⁺¹ = Vⁿ (1 + τ tr D/2) / (1 − τ tr D/2),
//           so that ΔV = τ tr D V^{n+1/2} and the pressure work −½(pⁿ + pⁿ⁺¹) ΔV is the rate
//           form's; ρ = m / V. The pair heat of the last forces (A_ij's work over the kick
//           that applied them) goes in here, as viscous heat.
//   forces: at x^{n+1} from σ^{n+1}: m_i dv_i/dt, the pair heat rate, and the stable step
//           τ_i = k h_i / (c_i + 1.2 (α c_i + β max_j μ_ij)).
//
// Symmetry planes act through mirror images ("ghosts") of the particles within reach of a
// plane: a ghost has its particle's fields reflected (position, velocity, the stress's
// off-diagonal terms that change sign), so a particle meets its image as the whole would.
//
// The bodies' faces: a particle within reach of a body's surface meets the body as it would the
// body's material made of particles like itself (its mirror image in the face), through the
// kernel's integrals over the faces (boundary.hpp: ∫_R ∇W dV' = −Σ n_k Φ_k). With the face's
// kernel-weighted point x_c = Σ w_v x_v and velocity v_f = Σ w_v v_v, v_if = v_i − v_f:
//
//   velocity gradient   L_i += v_if ⊗ n Φ
//   momentum            m_i dv_i/dt += −m_i ρ_i Φ (2 σ_i/ρ_i² − Π_if) n,  the face's nodes the
//                       opposite, node v its share w_v
//   energy              the pair's work beyond the particle's own σ_i : D_i, m_i ρ_i Φ v_if ·
//                       (σ_i/ρ_i² − Π_if) n, is the particle's heat (as the pairs' A_ij work)
//
// with Π_if Monaghan's viscosity at the particle's own ρ and c. A uniform stress exerts no
// force across a face (the kernel's part inside the body gives back what the particles' sums
// lack). A face meets the particle only while they approach (at the face's centroid velocity)
// or it presses (n·σ_i n < 0): no tension holds a particle to another body. Mirror images of the
// particles meet the faces too, so that a body cut by a symmetry plane is met whole.
//
// Determinism: every particle gathers its own sums over its neighbours in ascending order, on
// the threads block by block; the step's minimum is taken in block order. Results are the same
// bit for bit for any number of threads.
#pragma once

#include <array>
#include <span>
#include <utility>
#include <vector>

#include "tetcontact/material/material.hpp"
#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {
class Archive;
}  // namespace tc

namespace tc::sph {

struct Options {
  double alpha = 1.0;              // α of Monaghan's viscosity (linear in μ)
  double beta = 2.0;               // β (quadratic)
  double artificial_stress = 0.3;  // ε of the artificial stress (0: off)
  double stress_exponent = 4.0;    // n of f_ijⁿ
  bool fracture = false;           // spall damage and loosening, as the tets'
  double step_factor = 0.6;  // k of the stable step (× the solver's cfl 0.5: 0.14 h / c at rest)
  double reach = 1.2;        // neighbour lists hold the pairs within reach × 2 h_ij
  bool faces = true;         // meet the bodies' faces through the kernel (else: contact)
};

/// A plane the particles are mirrored across: they lie where side (x[axis] − at) ≥ 0. A
/// symmetry plane of the model has side +1; two planes of one axis (a column between walls)
/// bound a slab, whose width must be at least the kernel's reach.
struct MirrorPlane {
  int axis = 0;
  double at = 0.0;
  double side = 1.0;
};

/// The points a particle meets: the particles 0 … n−1, then mirror images (ghosts), each of a
/// particle (`ghost_source`) across a set of planes (`ghost_planes`, bit k: plane k). For
/// particle i, its neighbours are list[begin[i] … begin[i + 1]), ascending, itself excluded.
struct Neighbours {
  std::vector<Index> begin, list;
  std::vector<Index> ghost_source;
  std::vector<unsigned> ghost_planes;
  Index particles = 0;
  Index pairs() const { return static_cast<Index>(list.size()); }
};

/// The candidates of the particles' pairs, as the detection's one broadphase update lists them
/// (broadphase/contact_candidates.hpp, `ContactCandidates::particles_at`, on its binding lists):
/// `pairs` (i, j) with i < j, sorted, holding every pair of particles within reach × 2 h_ij at
/// the positions the stage is given; `faces` (i, f) sorted, holding every face (an index into
/// the faces the stage is given) whose box lies within reach × 2 h_i of particle i. Lists that
/// hold more are filtered to these.
struct Candidates {
  std::span<const std::pair<Index, Index>> pairs, faces;
};

/// The neighbours within reach × 2 h_ij of every particle at positions x (one per particle), of
/// the candidate pairs (i < j, holding every such pair), with the mirror images', sorted (the
/// brute-force search gives the same lists; tested).
Neighbours find_neighbours(const std::vector<Vec3>& x, const std::vector<double>& h,
                           const std::vector<MirrorPlane>& planes, double reach,
                           std::span<const std::pair<Index, Index>> pairs);

/// The planes as mesh/symmetry.hpp reflects across them (mirror_image, mirror_direction: plane k
/// is bit k of a mask); `side` only says which of its sides holds the particles.
std::vector<SymmetryPlane> symmetry_planes(const std::vector<MirrorPlane>& planes);
/// Image of a stress across the planes of `mask`.
Sym6 mirror_stress(Sym6 s, const std::vector<SymmetryPlane>& planes, unsigned mask);

/// What a force pass found: the stable step (before the solver's cfl) and the particle that
/// sets it.
struct StepLimit {
  double dt_stable = 0.0;
  Index critical = -1;
};

/// The SPH stage of a run: its options, planes and working arrays over State::sph.
class Stage {
 public:
  Stage(Options options, std::vector<MirrorPlane> planes)
      : options_(options), planes_(std::move(planes)), symmetry_(symmetry_planes(planes_)) {}

  /// The material update over the step τ (see above), from st.v (U^{n+1/2}) and st.x
  /// (x^{n+1}); tau_kick: the step over which the last forces were applied to the velocities
  /// (the pair heat's). Throws RunFailure naming the particle for a non-finite state.
  /// `faces`: the bodies' surface faces (outward by the right-hand rule), met through the kernel
  /// with Options::faces; `candidates`: the particles' candidate pairs at st.x.
  void update(const std::vector<Material>& materials, double tau, double tau_kick, State& st,
              const std::vector<Face>& faces, const Candidates& candidates);

  /// The forces at the current state into st.f (the particles' nodes; the faces' share added
  /// to their nodes' forces), the pair heat rate kept for the next update, and the stable step;
  /// the candidates as update's (used when update has not found the lists at st.x).
  StepLimit forces(State& st, const std::vector<Face>& faces, const Candidates& candidates);

  /// Per particle, the part of the last forces that its and its neighbours' mirror images
  /// exert: the symmetry planes' reaction, an external force to the model (the balance books
  /// its impulse as the planes').
  const std::vector<Vec3>& plane_forces() const { return plane_force_; }
  /// Σ_i of the last forces' pair heat rates, J/s (their viscosity's and the faces' work beyond
  /// the particles' own σ : D), in particle order: the next update books it over the whole
  /// kick these forces give; a balance taken within that kick counts its part.
  double heat_rate() const {
    double sum = 0.0;
    for (const double rate : heat_rate_) sum += rate;
    return sum;
  }
  const Neighbours& neighbours() const { return neighbours_; }
  const Options& options() const { return options_; }
  /// The face pairs of the last forces: (particle or mirror image, face) within reach.
  std::size_t face_pairs() const { return face_list_.size(); }
  /// What a checkpoint holds of it: the last forces' lists and terms, which the next step reads.
  void persist(Archive& ar);

 private:
  void find(const State& st, const std::vector<Face>& faces, const Candidates& candidates);
  // The step's terms of the particle's points (itself, then its images) with the faces.
  struct FaceTerm {
    using archive_bitwise = void;  // plain numbers (model/archive.hpp)
    Index particle;
    unsigned mask;  // of the image (0: the particle)
    Face face;      // its nodes
    std::array<double, 3> w;
    Vec3 coef;    // the heat's: rate = coef · v_if, in the point's frame
    Vec3 force;   // on the point (the face's nodes take −w_v of it)
    Vec3 v_face;  // Σ_v w_v v_v at the forces
  };
  struct PairTerms {
    Vec3 g;
    Sym6 a;
    double mu;
    bool extra;  // A_ij ≠ 0
  };
  PairTerms pair_terms(const ParticleMatter& pm, std::size_t i, std::size_t k, Index j,
                       const Vec3& r, const Vec3& dv) const;
  std::vector<double> kick_heat(const State& st, double tau_kick) const;
  Options options_;
  std::vector<MirrorPlane> planes_;
  std::vector<SymmetryPlane> symmetry_;  // the same planes, to reflect across
  Neighbours neighbours_;
  std::vector<Vec3> x_, v_;                // the points: the particles, then the ghosts
  std::vector<Sym6> stress_, art_;         // per point: σ/ρ², and R (the artificial stress)
  std::vector<double> heat_rate_;          // per particle: −½ Σ_j m_i m_j v_ij·A_ij ∇W, J/s
  std::vector<Vec3> plane_force_;          // per particle: the mirror images' part of the force
  std::vector<Vec3> pair_ag_;              // per neighbour entry: the last forces' A_ij ∇_i W_ij
  std::vector<unsigned char> pair_extra_;  // … where A_ij ≠ 0
  std::vector<FaceTerm> face_terms_;       // the last forces' face terms, by particle
  std::vector<Index> term_begin_;          // per particle: its terms [begin, end)
  std::vector<Index> ghost_begin_;         // per particle: its images n + [begin, end)
  std::vector<Index> face_begin_, face_list_;  // per point: the faces within its reach
  bool fresh_ = false;                         // the lists are of the current positions (update's)
};

/// Appends a particle of `material` (m its law) at its reference state (ρ0, no stress, no
/// energy, its start temperature) with reference volume vol0 and smoothing length h to the
/// particles' material; returns its index. Its node (mass ρ0 vol0, position, velocity) is the
/// caller's to append.
Index append_matter(ParticleMatter& pm, const Material& m, Index material, double vol0, double h);

/// Appends the particle a cell of material m becomes: the cell's state as it stands (deviator,
/// pressure, plastic strain, damage, temperature, sound speed, material; its volume, but for a
/// cell stretched beyond the volume where its pressure at the particle's energy `energy` is
/// zero: that volume, and for a compressed cell whose EOS reads more than the cell's pressure
/// at that energy, as under the average nodal pressure: the larger volume where it reads the
/// cell's pressure, at most 2 V0), density mass/V, smoothing length h. Its internal energy is the
/// particle's (State::particle_energy), its mass, position and velocity its node's, both the
/// caller's.
Index append_cell_matter(ParticleMatter& pm, const State& st, Index tet, double mass, double h,
                         const Material& m, double energy);

}  // namespace tc::sph
