#include "tetcontact/element/element.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>

#include "tetcontact/element/distributed.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {

namespace {

[[noreturn]] void inverted(Index t, const char* when, double vol, double vol0) {
  std::ostringstream os;
  os << "inverted " << when << " (volume " << vol << " m^3, reference " << vol0 << " m^3)";
  throw InvertedElement(t, os.str());
}

// Dobritsa et al.'s spall criterion: the largest principal stress σ1 = λmax(s) − p exceeds σ*. For
// a deviator λmax(s) ≤ √(2/3) |s|, which clears most cells without an eigenvalue solve.
bool spalls(const Material& m, const Sym6& s, double p) {
  if (!(m.spall_strength > 0.0)) return false;
  const double n2 =
      s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
  if (std::sqrt(2.0 / 3.0 * n2) * (1.0 + 1e-9) - p <= m.spall_strength) return false;
  Eigen::SelfAdjointEigenSolver<Mat3> es;
  es.computeDirect(to_mat3(s), Eigen::EigenvaluesOnly);
  return es.eigenvalues().maxCoeff() - p > m.spall_strength;
}

// Failure at the end of the step (Dobritsa et al.): an intact cell that spalls is damaged, its
// deviator dropped; a damaged cell loosened past χ = 1 − V0/V > χ* is destroyed. Returns the
// pressure the cell may carry: none in tension once damaged; a destroyed cell none while it
// is loosened (χ > 0), and its EOS pressure again only once pressed back below its reference
// volume (μ > 0): with no pressure at all, destroyed cells that neighbours compress again
// collapse, and the spall plate's step fell to 3e-14 s.
double fail(const Material& m, Index t, double vol, double p, State& st) {
  Damage& dmg = st.damage[t];
  if (dmg == Damage::intact && spalls(m, st.s[t], p)) {
    dmg = Damage::damaged;
    st.s[t] = Sym6{0, 0, 0, 0, 0, 0};
  }
  const double chi = 1.0 - st.vol0[t] / vol;
  if (dmg == Damage::damaged && chi > m.loosening_limit) dmg = Damage::destroyed;
  if (dmg == Damage::intact) return p;
  if (p < 0.0 || (dmg == Damage::destroyed && chi > 0.0)) return 0.0;
  return p;
}

// The energy at the end of the step with the EOS pressure it implies:
//   E^{n+1} = E + W − ½ (pⁿ + p^{n+1}) ΔV,  p^{n+1} = A(μ) + B E^{n+1}/V0,
// solved for E^{n+1}; `e` holds Eⁿ and the work done before the pressure's, `w` the rest.
inline double implicit_energy(double e, double w, double p_old, const EosTerms& eos, double dvol,
                              double vol0) {
  return (e - 0.5 * (p_old + eos.a) * dvol + w) / (1.0 + 0.5 * eos.b * dvol / vol0);
}

// Squared dilatational sound speed of the current state: (ρ c_b² + 4G/3) / ρ, with G at the
// state (Steinberg–Guinan's G(P, T) rises with pressure).
inline double sound_speed2(const Material& m, double mu, double p, const EosTerms& t,
                           double temperature) {
  const double rho = m.density * (1.0 + mu);
  const double g = shear_modulus_at(m, p, temperature, 1.0 + mu);
  return (bulk_stiffness(m, mu, p, t) + 4.0 / 3.0 * g) / rho;
}

// The geometry of a tet in plain doubles: edge vectors from node 0, the outward area vectors
// a1..a3 of the faces opposite nodes 1..3 (a0 = −(a1 + a2 + a3)), the volume
// V = −e1·a1 / 3, and the largest squared face area.
struct TetGeometry {
  double a[4][3];
  double vol;
  double amax2;
};

[[gnu::always_inline]] inline void tet_geometry(const double e[3][3], TetGeometry& g) {
  auto cross_half = [](const double* u, const double* v, double* out) {
    out[0] = 0.5 * (u[1] * v[2] - u[2] * v[1]);
    out[1] = 0.5 * (u[2] * v[0] - u[0] * v[2]);
    out[2] = 0.5 * (u[0] * v[1] - u[1] * v[0]);
  };
  cross_half(e[2], e[1], g.a[1]);  // face (0,3,2)
  cross_half(e[0], e[2], g.a[2]);  // face (0,1,3)
  cross_half(e[1], e[0], g.a[3]);  // face (0,2,1)
  for (int d = 0; d < 3; ++d) g.a[0][d] = -(g.a[1][d] + g.a[2][d] + g.a[3][d]);
  g.vol = -(e[0][0] * g.a[1][0] + e[0][1] * g.a[1][1] + e[0][2] * g.a[1][2]) * (1.0 / 3.0);
  g.amax2 = 0.0;
  for (int i = 0; i < 4; ++i)
    g.amax2 =
        std::max(g.amax2, g.a[i][0] * g.a[i][0] + g.a[i][1] * g.a[i][1] + g.a[i][2] * g.a[i][2]);
}

[[gnu::always_inline]] inline void end_geometry(Index t, const Tet& k, const State& st,
                                                TetGeometry& g, const char* when) {
  const Vec3& x0 = st.x[k[0]];
  double e[3][3];
  for (int i = 0; i < 3; ++i)
    for (int d = 0; d < 3; ++d) e[i][d] = st.x[k[i + 1]][d] - x0[d];
  tet_geometry(e, g);
  if (!std::isfinite(g.vol)) throw InvertedElement(t, "non-finite node position");
  if (!(g.vol > 0.0)) inverted(t, when, g.vol, st.vol0[t]);
}

// Forces of one tet from its current stress σ = s − (p + q) I and its current geometry, and
// its CFL limit:
//   f_i = σ a_i / 3 (f_0 = −(f_1 + f_2 + f_3): each tet's forces balance),
//   τ_t = l / (Q + sqrt(Q² + c²)), l = 3V / max|a_i|, Q = C1 c + C2 l |ε̇v| in compression.
// The forces go to the tet's own corners f[0..3]; gather_forces adds them at the nodes.
[[gnu::always_inline]] inline void tet_forces(Index t, const TetGeometry& g,
                                              const ElementOptions& options, const State& st,
                                              Vec3* f, ForceResult& r) {
  const Sym6& s = st.s[t];
  const double pq = st.p[t] + st.q[t];
  constexpr double third = 1.0 / 3.0;  // σ/3, so that f_i = (σ/3) a_i
  const double sxx = (s[0] - pq) * third, syy = (s[1] - pq) * third, szz = (s[2] - pq) * third;
  const double sxy = s[3] * third, syz = s[4] * third, sxz = s[5] * third;
  double f0[3] = {0.0, 0.0, 0.0};
  for (int i = 1; i < 4; ++i) {
    const double* a = g.a[i];
    const double fx = sxx * a[0] + sxy * a[1] + sxz * a[2];
    const double fy = sxy * a[0] + syy * a[1] + syz * a[2];
    const double fz = sxz * a[0] + syz * a[1] + szz * a[2];
    f[i] = Vec3(fx, fy, fz);
    f0[0] += fx;
    f0[1] += fy;
    f0[2] += fz;
  }
  f[0] = Vec3(-f0[0], -f0[1], -f0[2]);
  // Compared as squares (r.dt_stable holds τ² until finish_forces): a tet in expansion needs
  // no square root at all.
  const double l2 = 9.0 * g.vol * g.vol / g.amax2;
  const double c2 = st.sound2[t];
  double dt2;
  if (st.trace_d[t] < 0.0) {
    const double c = std::sqrt(c2), l = std::sqrt(l2);
    const double qs =
        options.viscosity_linear * c + options.viscosity_quadratic * l * -st.trace_d[t];
    const double dt = l / (qs + std::sqrt(qs * qs + c2));
    dt2 = dt * dt;
  } else {
    dt2 = l2 / c2;
  }
  if (dt2 < r.dt_stable) {
    r.dt_stable = dt2;
    r.critical_tet = t;
  }
  if (dt2 < options.erode_dt2) r.eroding.push_back(t);
}

std::vector<ForceResult> block_results(std::size_t tets) {
  ForceResult none;
  none.dt_stable = std::numeric_limits<double>::infinity();
  return std::vector<ForceResult>(parallel::block_count(tets), none);
}

// The node–tet incidence, once per mesh (tets never change; particles are skipped by damage).
void build_incidence(const std::vector<Tet>& tets, std::size_t nodes, ElementScratch& scratch) {
  if (scratch.incidence.size() == 4 * tets.size() && !tets.empty()) return;
  scratch.incidence_begin.assign(nodes + 1, 0);
  for (const Tet& k : tets)
    for (Index a : k) ++scratch.incidence_begin[a + 1];
  for (std::size_t a = 0; a < nodes; ++a)
    scratch.incidence_begin[a + 1] += scratch.incidence_begin[a];
  scratch.incidence.resize(4 * tets.size());
  std::vector<Index> next(scratch.incidence_begin.begin(), scratch.incidence_begin.end() - 1);
  for (std::size_t t = 0; t < tets.size(); ++t)
    for (int c = 0; c < 4; ++c)
      scratch.incidence[next[tets[t][c]]++] = static_cast<Index>(4 * t + c);
  scratch.tet_force.assign(4 * tets.size(), Vec3::Zero());
}

// The squared minimum of scatter_forces back to a time step.
inline ForceResult finish_forces(ForceResult r) {
  r.dt_stable = std::sqrt(r.dt_stable);
  return r;
}

}  // namespace

void init_sound_speed(const std::vector<Material>& materials, State& st) {
  for (std::size_t t = 0; t < st.vol.size(); ++t) {
    const Material& m = materials[st.tet_material[t]];
    const double mu = st.vol0[t] / st.vol[t] - 1.0;
    st.sound2[t] = sound_speed2(m, mu, st.p[t], eos_terms(m, mu), st.temperature[t]);
  }
}

ForceResult compute_forces(const std::vector<Tet>& tets, const ElementOptions& options, State& st,
                           ElementScratch& scratch) {
  const std::size_t mesh_nodes = static_cast<std::size_t>(st.first_particle);
  build_incidence(tets, mesh_nodes, scratch);
  if (distributed(scratch)) build_distribution(tets, mesh_nodes, scratch);
  const MyTets mine(scratch, tets.size());
  std::vector<ForceResult> blocks = block_results(mine.size());
  const ForceResult r = collective_pass(scratch, blocks, [&] {
    parallel::for_blocks(mine.size(), [&](std::size_t blk, std::size_t begin, std::size_t end) {
      TetGeometry g;
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t t = mine[i];
        if (st.damage[t] == Damage::particle) continue;
        const Index ti = static_cast<Index>(t);
        end_geometry(ti, tets[t], st, g, "");
        tet_forces(ti, g, options, st, &scratch.tet_force[4 * t], blocks[blk]);
      }
    });
  });
  gather_forces(mesh_nodes, scratch, st);
  return finish_forces(r);
}

namespace {

// Whether material `mat` takes the average nodal pressure.
bool averages_pressure(const ElementOptions& options, Index mat) {
  return mat < static_cast<Index>(options.average_nodal_pressure.size()) &&
         options.average_nodal_pressure[mat];
}

// The arrays of the nodal averages: the nodal reference volumes and materials once, the rest
// cleared each step.
void prepare_averages(const std::vector<Tet>& tets, const ElementOptions& options, const State& st,
                      ElementScratch& scratch) {
  const std::size_t n = st.x.size();
  if (scratch.vol0.size() != n) {
    scratch.vol0.assign(n, 0.0);
    scratch.node_material.assign(n, -1);
    for (std::size_t t = 0; t < tets.size(); ++t)
      for (Index k : tets[t]) {
        scratch.vol0[k] += 0.25 * st.vol0[t];
        // Nodes of one body share its material.
        if (averages_pressure(options, st.tet_material[t]))
          scratch.node_material[k] = st.tet_material[t];
      }
  }
  scratch.pressure.assign(n, 0.0);
  scratch.node_j.assign(n, 1.0);
  scratch.tet_dvol.assign(tets.size(), 0.0);
  scratch.tet_energy.assign(tets.size(), 0.0);
  scratch.tet_averaged.assign(tets.size(), 0);
}

// One cell's motion over the step: its geometry at mid-step (x^{n+1/2} = x^{n+1} − τ/2 U^{n+1})
// and at the end, and the rate of deformation D, the spin W and tr D from the velocity gradient
// at mid-step.
struct CellKinematics {
  TetGeometry gm, ge;
  Sym6 d;
  std::array<double, 3> w;
  double trD;
};

[[gnu::always_inline]] inline void cell_kinematics(Index ti, const Tet& k, double tau,
                                                   const State& st, CellKinematics& c) {
  const double h = 0.5 * tau;
  // Edges at the end of the step and at mid-step, and the velocity differences U_i − U_0.
  const Vec3 &x0 = st.x[k[0]], &u0 = st.v[k[0]];
  double ee[3][3], em[3][3], du[3][3];
  for (int i = 0; i < 3; ++i) {
    const Vec3 &xi = st.x[k[i + 1]], &ui = st.v[k[i + 1]];
    for (int d = 0; d < 3; ++d) {
      ee[i][d] = xi[d] - x0[d];
      du[i][d] = ui[d] - u0[d];
      em[i][d] = ee[i][d] - h * du[i][d];
    }
  }
  const double vol0 = st.vol0[ti];
  tet_geometry(em, c.gm);
  if (!(c.gm.vol > 0.0)) inverted(ti, "during the step", c.gm.vol, vol0);
  tet_geometry(ee, c.ge);
  if (!std::isfinite(c.ge.vol)) throw InvertedElement(ti, "non-finite node position");
  if (!(c.ge.vol > 0.0)) inverted(ti, "at the end of the step", c.ge.vol, vol0);

  // L = Σ_i (U_i − U_0) ⊗ ∇N_i, ∇N_i = −a_i / (3V) at mid-step.
  double L[3][3];
  const double inv3v = -1.0 / (3.0 * c.gm.vol);
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col)
      L[r][col] = inv3v * (du[0][r] * c.gm.a[1][col] + du[1][r] * c.gm.a[2][col] +
                           du[2][r] * c.gm.a[3][col]);
  c.d = Sym6{L[0][0],
             L[1][1],
             L[2][2],
             0.5 * (L[0][1] + L[1][0]),
             0.5 * (L[1][2] + L[2][1]),
             0.5 * (L[0][2] + L[2][0])};
  c.w = {0.5 * (L[2][1] - L[1][2]), 0.5 * (L[0][2] - L[2][0]), 0.5 * (L[1][0] - L[0][1])};
  c.trD = c.d[0] + c.d[1] + c.d[2];
}

// The deviator (Jaumann rate, radial return; none in a failed cell) and its trapezoidal work
// τ V ½(sⁿ + sⁿ⁺¹) : D, returned; the plastic work V σy Δε̄p into `w_p` (bilinear with σy at
// mid-increment, exact for linear hardening; the other laws at the end of the step, the heating
// their return assumed), the plastic strain, and the cell listed as eroding when it reaches the
// strain limit or Johnson–Cook's ductile damage D = 1:
//   D += Δε̄p / ε_f(σ*, ε̇p, T),  σ* = −p / σ_eq  (the start's pressure, the returned deviator);
// the increments taken with ε_f at its floor are also summed apart (`ductile_floor`), or left
// out where the material has no ductile failure at the floor.
[[gnu::always_inline]] inline double deviator_work(Index t, const Material& mat,
                                                   const CellKinematics& c, double rho_mid,
                                                   const ElementOptions& options, double tau,
                                                   State& st, ForceResult& block, double& w_p) {
  const Sym6 s_old = st.s[t];
  const bool failed = options.fracture && st.damage[t] != Damage::intact;
  const DeviatorIncrement inc = failed ? DeviatorIncrement{}
                                       : update_deviator6(mat, st.s[t], c.d, c.w, tau, st.eps_p[t],
                                                          st.temperature[t], rho_mid, st.p[t]);
  const Sym6& s_new = st.s[t];
  double sd = 0.0;
  for (int k = 0; k < 6; ++k) sd += (k < 3 ? 1.0 : 2.0) * (s_old[k] + s_new[k]) * c.d[k];
  const double w_dev = 0.5 * tau * c.gm.vol * sd;
  w_p = 0.0;
  if (inc.dplastic > 0.0) {
    const double y = mat.strength == StrengthModel::bilinear
                         ? inc.yield - 0.5 * mat.hardening_modulus * inc.dplastic
                         : inc.yield;
    w_p = c.gm.vol * y * inc.dplastic;
    st.w_plastic[t] += w_p;
    st.eps_p[t] += inc.dplastic;
    if (mat.erosion_plastic_strain > 0.0 && st.eps_p[t] >= mat.erosion_plastic_strain)
      block.eroding.push_back(t);
    if (mat.ductile_failure) {
      const double eq = von_mises(s_new);
      const double triax = eq > 0.0 ? -st.p[t] / eq : 0.0;
      const double ef = johnson_cook_failure_strain(mat.johnson_cook_failure, triax,
                                                    inc.dplastic / tau, st.temperature[t]);
      const bool floored = ef <= mat.johnson_cook_failure.min_strain;
      if (!floored || mat.ductile_failure_at_floor) {
        st.ductile[t] += inc.dplastic / ef;
        if (floored) st.ductile_floor[t] += inc.dplastic / ef;
      }
      if (st.ductile[t] >= 1.0) block.eroding.push_back(t);
    }
  }
  return w_dev;
}

// Viscosity from the mid-step strain rate, in compression only; its work, returned, is the
// trapezoid of the values at both ends of the step (q^{n+1/2} is what the forces at t^{n+1}
// carry), as for the pressure. The cell takes its end volume (`dvol` the change) and the heat:
// the viscous (shock) heat and the fraction χ of the plastic work.
[[gnu::always_inline]] inline double viscous_work(Index t, const Material& mat,
                                                  const CellKinematics& c, double rho_mid,
                                                  double w_p, const ElementOptions& options,
                                                  State& st, double& dvol) {
  double q = 0.0;
  if (c.trD < 0.0) {
    const double l = 3.0 * c.gm.vol / std::sqrt(c.gm.amax2);
    q = bulk_viscosity(rho_mid, l, std::sqrt(st.sound2[t]), c.trD, options.viscosity_linear,
                       options.viscosity_quadratic);
  }
  dvol = c.ge.vol - st.vol[t];
  const double w_q = -0.5 * (st.q[t] + q) * dvol;
  st.q[t] = q;
  st.trace_d[t] = c.trD;
  st.w_viscous[t] += w_q;
  st.vol[t] = c.ge.vol;
  if (mat.thermal())
    st.temperature[t] +=
        (mat.taylor_quinney * w_p + w_q) / (mat.density * st.vol0[t] * mat.specific_heat);
  return w_q;
}

// Per-tet pressure, p^{n+1} = A(μ) + B E^{n+1}/V0 with
//   E^{n+1} = E^n + W_dev − ½ (p^n + p^{n+1}) ΔV + W_q, solved for E^{n+1},
// failure (the pressure a failed cell carries, its energy with it), the sound speed, and the
// cell's forces from its end geometry.
[[gnu::always_inline]] inline void cell_pressure(Index t, const Material& mat,
                                                 const CellKinematics& c, double w_dev, double w_q,
                                                 double dvol, const ElementOptions& options,
                                                 State& st, Vec3* f, ForceResult& block) {
  const double mu = st.vol0[t] / c.ge.vol - 1.0;
  const EosTerms eos = eos_terms(mat, mu);
  double e_new = implicit_energy(st.e_int[t] + w_dev, w_q, st.p[t], eos, dvol, st.vol0[t]);
  double p_new = eos.a + eos.b * e_new / st.vol0[t];
  if (options.fracture) {
    const double carried = fail(mat, t, c.ge.vol, p_new, st);
    if (carried != p_new) {
      p_new = carried;
      e_new = st.e_int[t] + w_dev - 0.5 * (st.p[t] + p_new) * dvol + w_q;
    }
  }
  st.e_int[t] = e_new;
  st.p[t] = p_new;
  st.sound2[t] = sound_speed2(mat, mu, st.p[t], eos, st.temperature[t]);
  tet_forces(t, c.ge, options, st, f, block);
}

// Pass 1 for one cell: kinematics, deviator, viscosity; with per-tet pressure also the EOS, the
// energy and the forces; with the average nodal pressure what pass 2 gathers (failed cells are
// left out of the averages: their neighbours' pressure must not depend on a loosened cell's
// volume — an intact cell beside spalled ones was crushed to V/V0 = 0.29 under an averaged
// pressure far below its own), the pressure work following in pass 3.
[[gnu::always_inline]] inline void update_cell(std::size_t t, const Tet& k,
                                               const std::vector<Material>& materials,
                                               const ElementOptions& options, double tau, State& st,
                                               ElementScratch& scratch, ForceResult& block) {
  const Index ti = static_cast<Index>(t);
  const Index mi = st.tet_material[t];
  const Material& mat = materials[mi];
  CellKinematics c;
  cell_kinematics(ti, k, tau, st, c);
  const double rho_mid = mat.density * st.vol0[t] / c.gm.vol;
  double w_p = 0.0, dvol = 0.0;
  const double w_dev = deviator_work(ti, mat, c, rho_mid, options, tau, st, block, w_p);
  const double w_q = viscous_work(ti, mat, c, rho_mid, w_p, options, st, dvol);
  if (averages_pressure(options, mi)) {
    scratch.tet_averaged[t] = !options.fracture || st.damage[t] == Damage::intact;
    scratch.tet_energy[t] = st.e_int[t];
    st.e_int[t] += w_dev + w_q;
    scratch.tet_dvol[t] = dvol;
    return;
  }
  cell_pressure(ti, mat, c, w_dev, w_q, dvol, options, st, &scratch.tet_force[4 * t], block);
}

// Pass 2: nodal volumes and energies gathered from the cells in the averages (a quarter of
// each), then nodal pressures from them (per reference volume); distributed, at the nodes of
// this rank's tets only (pass 3 reads no other).
void nodal_pressures(const std::vector<Material>& materials, const ElementOptions& options,
                     std::size_t mesh_nodes, const State& st, ElementScratch& scratch) {
  const std::size_t averaged_nodes = distributed(scratch) ? scratch.my_nodes.size() : mesh_nodes;
  parallel::for_each(averaged_nodes, [&](std::size_t i) {
    const std::size_t n = distributed(scratch) ? static_cast<std::size_t>(scratch.my_nodes[i]) : i;
    const Index nm = scratch.node_material[n];
    if (nm < 0) return;
    double vol = 0.0, energy = 0.0, vol0 = 0.0;
    for (Index e = scratch.incidence_begin[n]; e < scratch.incidence_begin[n + 1]; ++e) {
      const Index t = scratch.incidence[e] >> 2;
      if (!scratch.tet_averaged[t]) continue;  // failed, a particle, or another material
      vol += 0.25 * st.vol[t];
      energy += 0.25 * scratch.tet_energy[t];
      vol0 += 0.25 * st.vol0[t];
    }
    if (options.fracture) scratch.vol0[n] = vol0;  // over the intact cells, each step
    if (!(vol > 0.0)) return;                      // every cell around it failed: not used
    const double mu = scratch.vol0[n] / vol - 1.0;
    scratch.pressure[n] = eos_pressure(materials[nm], mu, energy / scratch.vol0[n]);
    scratch.node_j[n] = vol / scratch.vol0[n];
  });
}

// Pass 3 for one cell of the average nodal pressure: its pressure the mean of its nodes',
// stabilized, its own EOS when failed; the trapezoidal pressure work; the forces.
[[gnu::always_inline]] inline void averaged_cell_pressure(std::size_t t, const Tet& k,
                                                          const Material& mat,
                                                          const ElementOptions& options, State& st,
                                                          ElementScratch& scratch,
                                                          ForceResult& block) {
  const Index ti = static_cast<Index>(t);
  const double mu = st.vol0[t] / st.vol[t] - 1.0, dvol = scratch.tet_dvol[t];
  const EosTerms eos = eos_terms(mat, mu);
  double p_new = 0.25 * (scratch.pressure[k[0]] + scratch.pressure[k[1]] + scratch.pressure[k[2]] +
                         scratch.pressure[k[3]]);
  // Stabilization: the averages leave a tet free to change its volume where its nodes' volumes
  // do not (a tet crushed to J = 0.36 under an averaged tension, at the axis of a Taylor rod);
  // α K (J̄ − J) / J resists only that difference, J̄ the mean of its nodes' volume ratios, and
  // vanishes where the tet follows its nodes.
  if (options.anp_stabilization > 0.0) {
    const double j = st.vol[t] / st.vol0[t];
    const double jbar = 0.25 * (scratch.node_j[k[0]] + scratch.node_j[k[1]] + scratch.node_j[k[2]] +
                                scratch.node_j[k[3]]);
    p_new += options.anp_stabilization * mat.bulk_modulus * (jbar - j) / j;
  }
  if (options.fracture && st.damage[t] != Damage::intact) {
    // A failed cell no longer averages its pressure with its neighbours' nodes (loosened
    // neighbours in tension would leave it no resistance to compression): its own EOS, the
    // energy solved implicitly as in the per-tet path.
    p_new = eos.a +
            eos.b * implicit_energy(st.e_int[t], 0.0, st.p[t], eos, dvol, st.vol0[t]) / st.vol0[t];
  }
  if (options.fracture) p_new = fail(mat, ti, st.vol[t], p_new, st);
  st.e_int[t] -= 0.5 * (st.p[t] + p_new) * dvol;
  st.p[t] = p_new;
  st.sound2[t] = sound_speed2(mat, mu, p_new, eos, st.temperature[t]);
  TetGeometry g;
  end_geometry(ti, k, st, g, "at the end of the step");
  tet_forces(ti, g, options, st, &scratch.tet_force[4 * t], block);
}

}  // namespace

// The element stage: pass 1 over the cells (update_cell); without the average nodal pressure the
// forces are then gathered; with it, pass 2 (nodal_pressures) and pass 3
// (averaged_cell_pressure) follow.
ForceResult update_material(const std::vector<Tet>& tets, const std::vector<Material>& materials,
                            const ElementOptions& options, double tau, State& st,
                            ElementScratch& scratch) {
  const std::size_t mesh_nodes = static_cast<std::size_t>(st.first_particle);
  build_incidence(tets, mesh_nodes, scratch);
  if (distributed(scratch)) build_distribution(tets, mesh_nodes, scratch);
  const bool any_anp = std::any_of(options.average_nodal_pressure.begin(),
                                   options.average_nodal_pressure.end(), [](char c) { return c; });
  if (any_anp) prepare_averages(tets, options, st, scratch);

  const MyTets mine(scratch, tets.size());
  std::vector<ForceResult> blocks = block_results(mine.size());
  ForceResult forces = collective_pass(scratch, blocks, [&] {
    parallel::for_blocks(mine.size(), [&](std::size_t blk, std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t t = mine[i];
        if (st.damage[t] == Damage::particle) continue;  // now a particle: no longer a cell
        update_cell(t, tets[t], materials, options, tau, st, scratch, blocks[blk]);
      }
    });
  });
  if (!any_anp) {
    gather_forces(mesh_nodes, scratch, st);
    if (distributed(scratch)) share_damaged(scratch, st, forces.eroding);
    return finish_forces(forces);
  }
  // Distributed: the inputs of the nodal averages at shared nodes, from the tets around them.
  if (distributed(scratch)) share_tets(scratch, st, k_averages, scratch.rank_frontier_tets);
  nodal_pressures(materials, options, mesh_nodes, st, scratch);
  blocks = block_results(mine.size());
  const ForceResult third = collective_pass(scratch, blocks, [&] {
    parallel::for_blocks(mine.size(), [&](std::size_t blk, std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t t = mine[i];
        const Index mi = st.tet_material[t];
        if (!averages_pressure(options, mi) || st.damage[t] == Damage::particle) continue;
        averaged_cell_pressure(t, tets[t], materials[mi], options, st, scratch, blocks[blk]);
      }
    });
  });
  merge(forces, {third});
  gather_forces(mesh_nodes, scratch, st);
  if (distributed(scratch)) share_damaged(scratch, st, forces.eroding);
  return finish_forces(forces);
}

}  // namespace tc
