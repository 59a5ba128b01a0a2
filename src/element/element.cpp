#include "tetcontact/element/element.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>

#include "tetcontact/element/distributed.hpp"
#include "tetcontact/element/material_point.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {

namespace {

[[noreturn]] void inverted(Index t, const char* when, double vol, double vol0) {
  std::ostringstream os;
  os << "inverted " << when << " (volume " << vol << " m^3, reference " << vol0 << " m^3)";
  throw InvertedElement(t, os.str());
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

// The CFL limit of one tet, squared:
//   τ_t = l / (Q + sqrt(Q² + c²)), l = 3V / max|a_i|, Q = C1 c + C2 l |ε̇v| in compression.
// Compared as squares (ForceResult::dt_stable holds τ² until finish_forces): a tet in expansion
// needs no square root at all.
[[gnu::always_inline]] inline double stable_step2(Index t, const TetGeometry& g,
                                                  const ElementOptions& options, const State& st) {
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
  return dt2;
}

// Forces of one tet from its current stress σ = s − (p + q) I and its current geometry, and
// its CFL limit (stable_step2):
//   f_i = σ a_i / 3 (f_0 = −(f_1 + f_2 + f_3): each tet's forces balance).
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
  const double dt2 = stable_step2(t, g, options, st);
  if (dt2 < r.dt_stable) {
    r.dt_stable = dt2;
    r.critical_tet = t;
  }
  if (!options.erode_dt2.empty() && dt2 < options.erode_dt2[options.tet_body[t]])
    r.eroding.push_back(t);
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
    st.sound2[t] =
        sound_speed2(m, mu, st.p[t], eos_terms(m, mu, st.e_int[t] / st.vol0[t]), st.temperature[t]);
  }
}

std::vector<double> body_stable_steps(const std::vector<Tet>& tets,
                                      const std::vector<Index>& tet_body, std::size_t bodies,
                                      const ElementOptions& options, const State& st) {
  std::vector<double> dt2(bodies, std::numeric_limits<double>::infinity());
  TetGeometry g;
  for (std::size_t t = 0; t < tets.size(); ++t) {
    if (st.damage[t] == Damage::particle) continue;
    const Index ti = static_cast<Index>(t);
    end_geometry(ti, tets[t], st, g, "");
    double& b = dt2[static_cast<std::size_t>(tet_body[t])];
    b = std::min(b, stable_step2(ti, g, options, st));
  }
  for (double& d : dt2) d = std::sqrt(d);
  return dt2;
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
  PointMotion m;  // D, the spin and tr D from the velocity gradient; the volumes gm's and ge's
};

// The checks of a cell's kinematics, made before its material is updated: inverted
// during the step or at its end, or moved to a non-finite position.
inline void check_kinematics(Index ti, const State& st, const CellKinematics& c) {
  const double vol0 = st.vol0[ti];
  if (!(c.gm.vol > 0.0)) inverted(ti, "during the step", c.gm.vol, vol0);
  if (!std::isfinite(c.ge.vol)) throw InvertedElement(ti, "non-finite node position");
  if (!(c.ge.vol > 0.0)) inverted(ti, "at the end of the step", c.ge.vol, vol0);
}

[[gnu::always_inline]] inline void cell_kinematics(const Tet& k, double tau, const State& st,
                                                   CellKinematics& c) {
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
  tet_geometry(em, c.gm);
  tet_geometry(ee, c.ge);

  // L = Σ_i (U_i − U_0) ⊗ ∇N_i, ∇N_i = −a_i / (3V) at mid-step.
  double L[3][3];
  const double inv3v = -1.0 / (3.0 * c.gm.vol);
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col)
      L[r][col] = inv3v * (du[0][r] * c.gm.a[1][col] + du[1][r] * c.gm.a[2][col] +
                           du[2][r] * c.gm.a[3][col]);
  set_rates(L, c.m);
  c.m.vol_mid = c.gm.vol;
  c.m.vol_end = c.ge.vol;
}

// The same kinematics for a block of cells at once, in SIMD lanes: node data gathered into a
// structure of arrays, every quantity computed lane by lane with exactly the operations, in the
// order, of cell_kinematics (tet_geometry, the gradient, set_rates), so that each lane's doubles
// are the scalar path's bit for bit (test `Element.LanesGiveTheScalarPathsState`). Both paths
// leave the checks to check_kinematics, called cell by cell in order.
constexpr int kLanes = 8;

struct LaneGeometry {
  double a[4][3][kLanes];
  double vol[kLanes], amax2[kLanes];
};

// tet_geometry in lanes: e[i][d][l] the edge vectors from node 0.
[[gnu::always_inline]] inline void lane_geometry(const double (&e)[3][3][kLanes], LaneGeometry& g) {
  for (int l = 0; l < kLanes; ++l) {
    // cross_half(e[2], e[1]) → a1, cross_half(e[0], e[2]) → a2, cross_half(e[1], e[0]) → a3
    g.a[1][0][l] = 0.5 * (e[2][1][l] * e[1][2][l] - e[2][2][l] * e[1][1][l]);
    g.a[1][1][l] = 0.5 * (e[2][2][l] * e[1][0][l] - e[2][0][l] * e[1][2][l]);
    g.a[1][2][l] = 0.5 * (e[2][0][l] * e[1][1][l] - e[2][1][l] * e[1][0][l]);
    g.a[2][0][l] = 0.5 * (e[0][1][l] * e[2][2][l] - e[0][2][l] * e[2][1][l]);
    g.a[2][1][l] = 0.5 * (e[0][2][l] * e[2][0][l] - e[0][0][l] * e[2][2][l]);
    g.a[2][2][l] = 0.5 * (e[0][0][l] * e[2][1][l] - e[0][1][l] * e[2][0][l]);
    g.a[3][0][l] = 0.5 * (e[1][1][l] * e[0][2][l] - e[1][2][l] * e[0][1][l]);
    g.a[3][1][l] = 0.5 * (e[1][2][l] * e[0][0][l] - e[1][0][l] * e[0][2][l]);
    g.a[3][2][l] = 0.5 * (e[1][0][l] * e[0][1][l] - e[1][1][l] * e[0][0][l]);
    for (int d = 0; d < 3; ++d) g.a[0][d][l] = -(g.a[1][d][l] + g.a[2][d][l] + g.a[3][d][l]);
    g.vol[l] =
        -(e[0][0][l] * g.a[1][0][l] + e[0][1][l] * g.a[1][1][l] + e[0][2][l] * g.a[1][2][l]) *
        (1.0 / 3.0);
    double amax2 = 0.0;
    for (int i = 0; i < 4; ++i) {
      const double n2 =
          g.a[i][0][l] * g.a[i][0][l] + g.a[i][1][l] * g.a[i][1][l] + g.a[i][2][l] * g.a[i][2][l];
      amax2 = amax2 < n2 ? n2 : amax2;  // std::max(amax2, n2)
    }
    g.amax2[l] = amax2;
  }
}

void copy_geometry(const LaneGeometry& g, int l, TetGeometry& out) {
  for (int i = 0; i < 4; ++i)
    for (int d = 0; d < 3; ++d) out.a[i][d] = g.a[i][d][l];
  out.vol = g.vol[l];
  out.amax2 = g.amax2[l];
}

// cell_kinematics for the cells tets[t[l]], l < count (lanes past count repeat the first).
// Two copies, AVX2 (four doubles a lane group) where the processor has it, SSE2 otherwise:
// neither contracts a product and a sum, so both give the scalar path's doubles.
__attribute__((target_clones("avx2", "default"))) void lane_kinematics(const std::size_t* t,
                                                                       int count,
                                                                       const std::vector<Tet>& tets,
                                                                       double tau, const State& st,
                                                                       CellKinematics* c) {
  const double h = 0.5 * tau;
  double ee[3][3][kLanes], em[3][3][kLanes], du[3][3][kLanes];
  for (int l = 0; l < kLanes; ++l) {
    const Tet& k = tets[t[l < count ? l : 0]];
    const Vec3 &x0 = st.x[k[0]], &u0 = st.v[k[0]];
    for (int i = 0; i < 3; ++i) {
      const Vec3 &xi = st.x[k[i + 1]], &ui = st.v[k[i + 1]];
      for (int d = 0; d < 3; ++d) {
        ee[i][d][l] = xi[d] - x0[d];
        du[i][d][l] = ui[d] - u0[d];
      }
    }
  }
  for (int i = 0; i < 3; ++i)
    for (int d = 0; d < 3; ++d)
      for (int l = 0; l < kLanes; ++l) em[i][d][l] = ee[i][d][l] - h * du[i][d][l];
  LaneGeometry gm, ge;
  lane_geometry(em, gm);
  lane_geometry(ee, ge);
  // L = Σ_i (U_i − U_0) ⊗ ∇N_i, ∇N_i = −a_i / (3V) at mid-step; then set_rates.
  double L[3][3][kLanes];
  for (int l = 0; l < kLanes; ++l) {
    const double inv3v = -1.0 / (3.0 * gm.vol[l]);
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col)
        L[r][col][l] = inv3v * (du[0][r][l] * gm.a[1][col][l] + du[1][r][l] * gm.a[2][col][l] +
                                du[2][r][l] * gm.a[3][col][l]);
  }
  for (int l = 0; l < count; ++l) {
    CellKinematics& k = c[l];
    copy_geometry(gm, l, k.gm);
    copy_geometry(ge, l, k.ge);
    double Ll[3][3];
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) Ll[r][col] = L[r][col][l];
    set_rates(Ll, k.m);
    k.m.vol_mid = gm.vol[l];
    k.m.vol_end = ge.vol[l];
  }
}

// Per-tet pressure (point_pressure: the EOS, the energy, failure, the sound speed) and the
// cell's forces from its end geometry.
[[gnu::always_inline]] inline void cell_pressure(Index t, const Material& mat,
                                                 const CellKinematics& c, double w_dev, double w_q,
                                                 double dvol, const ElementOptions& options,
                                                 State& st, Vec3* f, ForceResult& block) {
  point_pressure(mat, w_dev, w_q, dvol, options.fracture, tet_point(st, t));
  tet_forces(t, c.ge, options, st, f, block);
}

// Pass 1 for one cell: kinematics, deviator, viscosity; with per-tet pressure also the EOS, the
// energy and the forces; with the average nodal pressure what pass 2 gathers (failed cells are
// left out of the averages: their neighbours' pressure must not depend on a loosened cell's
// volume — an intact cell beside spalled ones was crushed to V/V0 = 0.29 under an averaged
// pressure far below its own), the pressure work following in pass 3.
[[gnu::always_inline]] inline void update_cell(std::size_t t, const CellKinematics& c,
                                               const std::vector<Material>& materials,
                                               const ElementOptions& options, double tau, State& st,
                                               ElementScratch& scratch, ForceResult& block) {
  const Index ti = static_cast<Index>(t);
  const Index mi = st.tet_material[t];
  const Material& mat = materials[mi];
  const MaterialPoint pt = tet_point(st, ti);
  const double rho_mid = mat.density * st.vol0[t] / c.gm.vol;
  double w_p = 0.0, dvol = 0.0;
  bool eroding = false;
  const bool failed = options.fracture && st.damage[t] != Damage::intact;
  const double w_dev = deviator_work(mat, c.m, c.m.d, rho_mid, failed, tau, pt, w_p, eroding);
  if (eroding) block.eroding.push_back(ti);
  // Viscosity from the mid-step strain rate, in compression only, over the smallest altitude.
  double q = 0.0;
  if (c.m.trace < 0.0) {
    const double l = 3.0 * c.gm.vol / std::sqrt(c.gm.amax2);
    q = bulk_viscosity(rho_mid, l, std::sqrt(st.sound2[t]), c.m.trace, options.viscosity_linear,
                       options.viscosity_quadratic);
  }
  const double w_q = viscous_work(mat, c.m, q, w_p, pt, dvol);
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
  EosTerms eos = eos_terms(mat, mu, st.e_int[t] / st.vol0[t]);
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
    const EnergySolve solved = solve_energy(mat, mu, st.e_int[t], 0.0, st.p[t], dvol, st.vol0[t]);
    p_new = solved.p;
    eos = solved.eos;
  }
  if (options.fracture) p_new = fail(mat, st.vol[t], p_new, tet_point(st, ti));
  st.e_int[t] -= 0.5 * (st.p[t] + p_new) * dvol;
  st.p[t] = p_new;
  st.sound2[t] = sound_speed2(mat, mu, p_new, eos, st.temperature[t]);
  TetGeometry g;
  end_geometry(ti, k, st, g, "at the end of the step");
  tet_forces(ti, g, options, st, &scratch.tet_force[4 * t], block);
}

}  // namespace

namespace {
std::atomic<bool> element_lanes{true};
}  // namespace

bool set_element_lanes(bool on) {
  return element_lanes.exchange(on);
}

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
      if (!element_lanes) {
        for (std::size_t i = begin; i < end; ++i) {
          const std::size_t t = mine[i];
          if (st.damage[t] == Damage::particle) continue;  // now a particle: no longer a cell
          CellKinematics c;
          cell_kinematics(tets[t], tau, st, c);
          check_kinematics(static_cast<Index>(t), st, c);
          update_cell(t, c, materials, options, tau, st, scratch, blocks[blk]);
        }
        return;
      }
      // The cells kLanes at a time: their kinematics in lanes, then each cell's checks and
      // material update in order.
      std::size_t lane_tet[kLanes];
      CellKinematics c[kLanes];
      for (std::size_t i = begin; i < end;) {
        int count = 0;
        for (; i < end && count < kLanes; ++i)
          if (st.damage[mine[i]] != Damage::particle) lane_tet[count++] = mine[i];
        if (count == 0) continue;
        lane_kinematics(lane_tet, count, tets, tau, st, c);
        for (int l = 0; l < count; ++l) {
          const std::size_t t = lane_tet[l];
          check_kinematics(static_cast<Index>(t), st, c[l]);
          update_cell(t, c[l], materials, options, tau, st, scratch, blocks[blk]);
        }
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
