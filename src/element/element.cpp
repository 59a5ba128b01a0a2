#include "tetcontact/element/element.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

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
// are the scalar path's bit for bit (test `Element.LanesGiveTheScalarPathsState`). The checks
// stay check_kinematics', cell by cell in order (lane_cells hands an inverted cell's block to it).
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

// The kinematics of kLanes cells as a structure of arrays: the geometry at mid-step and at the
// end, and the rates of set_rates (D, the spin's axial vector, tr D).
struct LaneKinematics {
  LaneGeometry gm, ge;
  double d[6][kLanes], w[3][kLanes], trace[kLanes];
};

// cell_kinematics for the cells tets[t[l]], l < count (lanes past count repeat the first).
[[gnu::always_inline]] inline void kinematics_in_lanes(const std::size_t* t, int count,
                                                       const std::vector<Tet>& tets, double tau,
                                                       const State& st, LaneKinematics& k) {
  const double h = 0.5 * tau;
  double ee[3][3][kLanes], em[3][3][kLanes], du[3][3][kLanes];
  for (int l = 0; l < kLanes; ++l) {
    const Tet& tet = tets[t[l < count ? l : 0]];
    const Vec3 &x0 = st.x[tet[0]], &u0 = st.v[tet[0]];
    for (int i = 0; i < 3; ++i) {
      const Vec3 &xi = st.x[tet[i + 1]], &ui = st.v[tet[i + 1]];
      for (int d = 0; d < 3; ++d) {
        ee[i][d][l] = xi[d] - x0[d];
        du[i][d][l] = ui[d] - u0[d];
      }
    }
  }
  for (int i = 0; i < 3; ++i)
    for (int d = 0; d < 3; ++d)
      for (int l = 0; l < kLanes; ++l) em[i][d][l] = ee[i][d][l] - h * du[i][d][l];
  lane_geometry(em, k.gm);
  lane_geometry(ee, k.ge);
  // L = Σ_i (U_i − U_0) ⊗ ∇N_i, ∇N_i = −a_i / (3V) at mid-step; then set_rates.
  for (int l = 0; l < kLanes; ++l) {
    const double inv3v = -1.0 / (3.0 * k.gm.vol[l]);
    double L[3][3];
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col)
        L[r][col] = inv3v * (du[0][r][l] * k.gm.a[1][col][l] + du[1][r][l] * k.gm.a[2][col][l] +
                             du[2][r][l] * k.gm.a[3][col][l]);
    k.d[0][l] = L[0][0];
    k.d[1][l] = L[1][1];
    k.d[2][l] = L[2][2];
    k.d[3][l] = 0.5 * (L[0][1] + L[1][0]);
    k.d[4][l] = 0.5 * (L[1][2] + L[2][1]);
    k.d[5][l] = 0.5 * (L[0][2] + L[2][0]);
    k.w[0][l] = 0.5 * (L[2][1] - L[1][2]);
    k.w[1][l] = 0.5 * (L[0][2] - L[2][0]);
    k.w[2][l] = 0.5 * (L[1][0] - L[0][1]);
    k.trace[l] = k.d[0][l] + k.d[1][l] + k.d[2][l];
  }
}

// Lane l's kinematics as one cell's.
void copy_kinematics(const LaneKinematics& k, int l, CellKinematics& c) {
  copy_geometry(k.gm, l, c.gm);
  copy_geometry(k.ge, l, c.ge);
  for (int i = 0; i < 6; ++i) c.m.d[i] = k.d[i][l];
  for (int i = 0; i < 3; ++i) c.m.w[i] = k.w[i][l];
  c.m.trace = k.trace[l];
  c.m.vol_mid = k.gm.vol[l];
  c.m.vol_end = k.ge.vol[l];
}

// cell_kinematics for the cells tets[t[l]], l < count, into c[l].
[[gnu::always_inline]] inline void lane_kinematics(const std::size_t* t, int count,
                                                   const std::vector<Tet>& tets, double tau,
                                                   const State& st, CellKinematics* c) {
  LaneKinematics k;
  kinematics_in_lanes(t, count, tets, tau, st, k);
  for (int l = 0; l < count; ++l) copy_kinematics(k, l, c[l]);
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

// Helpers of the lanes, each the scalar path's operations for one lane, inlined into the lane
// loops that call them.

// eos_terms of a linear or Mie–Grüneisen material at compression m: A, B and ∂A/∂μ.
[[gnu::always_inline]] inline void eos_in_lane(const Material& mat, double m, double& a, double& b,
                                               double& da) {
  const double k0 = mat.density * mat.c0 * mat.c0;
  const bool linear = mat.eos == EosKind::linear;
  const double num = m * (1.0 + (1.0 - 0.5 * mat.gamma0) * m);
  const double den = 1.0 - (mat.s - 1.0) * m;
  const double dnum = 1.0 + 2.0 * (1.0 - 0.5 * mat.gamma0) * m;
  const double a_mg = k0 * num / (den * den);
  const double da_mg = k0 * (dnum * den + 2.0 * (mat.s - 1.0) * num) / (den * den * den);
  a = linear ? mat.bulk_modulus * m : m <= 0.0 ? k0 * m : a_mg;
  b = linear ? 0.0 : mat.gamma0;
  da = linear ? mat.bulk_modulus : m <= 0.0 ? k0 : da_mg;
}

// sound_speed2 with bulk_stiffness (floored at 1e-3 K) and the shear modulus g of the state.
[[gnu::always_inline]] inline double sound2_in_lane(const Material& mat, double mu, double p,
                                                    double b, double da, double g) {
  const double rho = mat.density * (1.0 + mu);
  const double k = (1.0 + mu) * da + b * p / (1.0 + mu);
  const double kf = 1e-3 * mat.bulk_modulus;
  return ((k < kf ? kf : k) + 4.0 / 3.0 * g) / rho;
}

// tet_forces for lane l: f_i = (σ/3) a_i, f_0 = −(f_1 + f_2 + f_3), σ = s − pq I on the end
// geometry g; and stable_step2, its step limit squared, from the sound speed c2 and tr D.
[[gnu::always_inline]] inline void forces_in_lane(
    int l, const LaneGeometry& g, const double (&s)[6][kLanes], double pq, double c2, double trace,
    const ElementOptions& options, double (&f)[4][3][kLanes], double (&dt2)[kLanes]) {
  constexpr double third = 1.0 / 3.0;
  const double sxx = (s[0][l] - pq) * third, syy = (s[1][l] - pq) * third,
               szz = (s[2][l] - pq) * third;
  const double sxy = s[3][l] * third, syz = s[4][l] * third, sxz = s[5][l] * third;
  double f0x = 0.0, f0y = 0.0, f0z = 0.0;
  for (int i = 1; i < 4; ++i) {
    const double ax = g.a[i][0][l], ay = g.a[i][1][l], az = g.a[i][2][l];
    const double fx = sxx * ax + sxy * ay + sxz * az;
    const double fy = sxy * ax + syy * ay + syz * az;
    const double fz = sxz * ax + syz * ay + szz * az;
    f[i][0][l] = fx;
    f[i][1][l] = fy;
    f[i][2][l] = fz;
    f0x += fx;
    f0y += fy;
    f0z += fz;
  }
  f[0][0][l] = -f0x;
  f[0][1][l] = -f0y;
  f[0][2][l] = -f0z;
  const double l2 = 9.0 * g.vol[l] * g.vol[l] / g.amax2[l];
  const double c = std::sqrt(c2), len = std::sqrt(l2);
  const double qs = options.viscosity_linear * c + options.viscosity_quadratic * len * -trace;
  const double dt = len / (qs + std::sqrt(qs * qs + c2));
  const double compressed = dt * dt, expanding = l2 / c2;
  dt2[l] = trace < 0.0 ? compressed : expanding;
}

// Lane l's forces to cell tl's corners, and its step limit into the block's (tet_forces' own
// bookkeeping); called in the cells' order.
inline void store_forces(int l, std::size_t tl, const double (&f)[4][3][kLanes], double dt2,
                         const ElementOptions& options, ElementScratch& scratch,
                         ForceResult& block) {
  Vec3* out = &scratch.tet_force[4 * tl];
  for (int i = 0; i < 4; ++i) out[i] = Vec3(f[i][0][l], f[i][1][l], f[i][2][l]);
  if (dt2 < block.dt_stable) {
    block.dt_stable = dt2;
    block.critical_tet = static_cast<Index>(tl);
  }
  if (!options.erode_dt2.empty() && dt2 < options.erode_dt2[options.tet_body[tl]])
    block.eroding.push_back(static_cast<Index>(tl));
}

// Pass 1 in lanes: cell_kinematics, check_kinematics and update_cell for the cells
// tets[t[l]], l < count, of one material. Their kinematics and state gathered into a structure
// of arrays, computed lane by lane with exactly the operations, in the order, of the scalar path
// (cell_kinematics; update_deviator6: the Jaumann rotation, the trial deviator, σ_eq, the
// bilinear law's return; deviator_work, bulk_viscosity and viscous_work), so that each lane's
// doubles are the scalar path's bit for bit, then scattered back; with per-tet pressure and a
// linear or Mie–Grüneisen EOS also point_pressure (solve_energy, sound_speed2) and tet_forces.
// Run cell by cell as scalar calls: Steinberg–Guinan's strength state, the return of
// Johnson–Cook and Steinberg–Guinan, ductile failure, failure (fail), and Tillotson's per-tet
// pressure (cell_pressure); the eroding cells listed in the cells' order, as the scalar path
// lists them. Lanes past count repeat the first cell.
// Returns false, having written nothing, where a cell's kinematics fail check_kinematics: the
// caller then takes the scalar path, which reports it (no exception leaves the lanes).
[[gnu::always_inline]] inline bool lane_cells(const std::size_t* t, int count,
                                              const std::vector<Tet>& tets, const Material& mat,
                                              const ElementOptions& options, double tau, State& st,
                                              ElementScratch& scratch, ForceResult& block) {
  LaneKinematics k;
  kinematics_in_lanes(t, count, tets, tau, st, k);
  for (int l = 0; l < count; ++l)
    if (!(k.gm.vol[l] > 0.0) || !std::isfinite(k.ge.vol[l]) || !(k.ge.vol[l] > 0.0)) return false;
  // Gather.
  const auto& d = k.d;
  const auto& w = k.w;
  const auto& trace = k.trace;
  const auto& vol_mid = k.gm.vol;
  const auto& vol_end = k.ge.vol;
  const auto& amax2 = k.gm.amax2;
  double s_old[6][kLanes], vol0[kLanes], vol[kLanes], q_old[kLanes], sound2[kLanes], eps_p[kLanes],
      w_plastic[kLanes], w_viscous[kLanes], temperature[kLanes], t_start[kLanes], e_int[kLanes],
      p_old[kLanes], shear[kLanes], failed[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    const std::size_t tl = t[l < count ? l : 0];
    for (int i = 0; i < 6; ++i) s_old[i][l] = st.s[tl][i];
    vol0[l] = st.vol0[tl];
    vol[l] = st.vol[tl];
    q_old[l] = st.q[tl];
    sound2[l] = st.sound2[tl];
    eps_p[l] = st.eps_p[tl];
    w_plastic[l] = st.w_plastic[tl];
    w_viscous[l] = st.w_viscous[tl];
    temperature[l] = st.temperature[tl];
    t_start[l] = temperature[l];
    e_int[l] = st.e_int[tl];
    p_old[l] = st.p[tl];
    shear[l] = mat.shear_modulus;
    failed[l] = options.fracture && st.damage[tl] != Damage::intact ? 1.0 : 0.0;
  }
  double rho_mid[kLanes];
  for (int l = 0; l < kLanes; ++l) rho_mid[l] = mat.density * vol0[l] / vol_mid[l];
  // Steinberg–Guinan's G(P, T) at the start of the step, cell by cell.
  const bool sg = mat.strength == StrengthModel::steinberg_guinan;
  StrengthState ss[kLanes];
  if (sg)
    for (int l = 0; l < count; ++l) {
      ss[l] = strength_state(mat, p_old[l], t_start[l],
                             rho_mid[l] > 0.0 ? rho_mid[l] / mat.density : 1.0);
      shear[l] = ss[l].g;
    }
  // update_deviator6: Q = (1 − c θ²) I + c A + c α αᵀ, α = τ w / 2; s* = Q s Qᵀ + 2G τ dev D;
  // σ_eq; the bilinear law's return in lanes.
  double s_new[6][kLanes], eq[kLanes], dplastic[kLanes], yield[kLanes];
  const bool plastic = mat.plastic(), bilinear = mat.strength == StrengthModel::bilinear;
  const double h_mod = mat.hardening_modulus;
  for (int l = 0; l < kLanes; ++l) {
    const Sym6 s = jaumann_trial(
        Sym6{s_old[0][l], s_old[1][l], s_old[2][l], s_old[3][l], s_old[4][l], s_old[5][l]},
        Sym6{d[0][l], d[1][l], d[2][l], d[3][l], d[4][l], d[5][l]}, {w[0][l], w[1][l], w[2][l]},
        tau, 2.0 * shear[l] * tau);
    const double s0 = s[0], s1 = s[1], s2 = s[2], s3 = s[3], s4 = s[4], s5 = s[5];
    const double n2 = s0 * s0 + s1 * s1 + s2 * s2 + 2.0 * (s3 * s3 + s4 * s4 + s5 * s5);
    eq[l] = std::sqrt(1.5 * n2);
    // plastic_increment, bilinear: σy = σy0 + H ε̄p; Δε̄p = (σ_eq − σy) / (3G + H) above it.
    const double y0 = mat.yield_stress + h_mod * (eps_p[l] + mat.initial_plastic_strain);
    const double dp = (eq[l] - y0) / (3.0 * shear[l] + h_mod);
    const bool yields = eq[l] > y0;
    const double y = yields ? y0 + h_mod * dp : y0;
    // An elastic material: no return, nothing scaled.
    dplastic[l] = plastic && yields ? dp : 0.0;
    yield[l] = plastic ? y : std::numeric_limits<double>::infinity();
    s_new[0][l] = s0;
    s_new[1][l] = s1;
    s_new[2][l] = s2;
    s_new[3][l] = s3;
    s_new[4][l] = s4;
    s_new[5][l] = s5;
  }
  // The other laws' return (plastic_increment, whose own bound on the yield clears an elastic
  // cell before its solver), cell by cell; none for a failed cell.
  if (plastic && !bilinear)
    for (int l = 0; l < count; ++l) {
      if (failed[l] != 0.0) continue;
      const StrengthState ssl =
          sg ? ss[l]
             : strength_state(mat, p_old[l], t_start[l],
                              rho_mid[l] > 0.0 ? rho_mid[l] / mat.density : 1.0);
      const PlasticIncrement inc =
          plastic_increment(mat, ssl, eq[l], eps_p[l], tau, t_start[l], rho_mid[l]);
      dplastic[l] = inc.dplastic;
      yield[l] = inc.yield;
    }
  // The radial return's scaling, a failed cell's deviator kept; deviator_work; bulk_viscosity;
  // viscous_work.
  double w_dev[kLanes], w_p[kLanes], q_new[kLanes], w_q[kLanes], dvol[kLanes];
  const double half_tau = 0.5 * tau, c1 = options.viscosity_linear,
               c2 = options.viscosity_quadratic;
  const bool thermal = mat.thermal();
  const double density = mat.density, chi = mat.taylor_quinney;
  for (int l = 0; l < kLanes; ++l) {
    const bool fl = failed[l] != 0.0;
    const double f = yield[l] < eq[l] ? yield[l] / eq[l] : 1.0;
    double sd = 0.0;
    for (int i = 0; i < 6; ++i) {
      const double sn = fl ? s_old[i][l] : s_new[i][l] * f;
      s_new[i][l] = sn;
      sd += (i < 3 ? 1.0 : 2.0) * (s_old[i][l] + sn) * d[i][l];
    }
    w_dev[l] = half_tau * vol_mid[l] * sd;
    const double dpl = fl ? 0.0 : dplastic[l];
    dplastic[l] = dpl;
    const double y = bilinear ? yield[l] - 0.5 * h_mod * dpl : yield[l];
    const double wp = vol_mid[l] * y * dpl;
    w_p[l] = dpl > 0.0 ? wp : 0.0;
    w_plastic[l] = dpl > 0.0 ? w_plastic[l] + wp : w_plastic[l];
    eps_p[l] = dpl > 0.0 ? eps_p[l] + dpl : eps_p[l];
    // Viscosity from the mid-step strain rate, in compression only, over the smallest altitude.
    const double len = 3.0 * vol_mid[l] / std::sqrt(amax2[l]);
    const double qv =
        rho_mid[l] * len * (c2 * len * trace[l] * trace[l] - c1 * std::sqrt(sound2[l]) * trace[l]);
    const double qn = trace[l] < 0.0 ? qv : 0.0;
    q_new[l] = qn;
    dvol[l] = vol_end[l] - vol[l];
    w_q[l] = -0.5 * (q_old[l] + qn) * dvol[l];
    w_viscous[l] = w_viscous[l] + w_q[l];
    const double heated =
        temperature[l] + (chi * w_p[l] + w_q[l]) / (density * vol0[l] * mat.specific_heat);
    temperature[l] = thermal ? heated : temperature[l];
  }
  // Scatter the deviator's and the viscosity's results; the cells' erosion by strain or damage.
  const bool averaged = averages_pressure(options, st.tet_material[t[0]]);
  bool eroding[kLanes];
  for (int l = 0; l < count; ++l) {
    const std::size_t tl = t[l];
    const Index ti = static_cast<Index>(tl);
    for (int i = 0; i < 6; ++i) st.s[tl][i] = s_new[i][l];
    st.eps_p[tl] = eps_p[l];
    st.w_plastic[tl] = w_plastic[l];
    // st.p and st.temperature are still the start's.
    eroding[l] = dplastic[l] > 0.0 && plastic_failure(mat, dplastic[l], tau, tet_point(st, ti));
    st.q[tl] = q_new[l];
    st.trace_d[tl] = trace[l];
    st.w_viscous[tl] = w_viscous[l];
    st.vol[tl] = vol_end[l];
    st.temperature[tl] = temperature[l];
    if (averaged) {
      scratch.tet_averaged[tl] = !options.fracture || st.damage[tl] == Damage::intact;
      scratch.tet_energy[tl] = e_int[l];
      st.e_int[tl] = e_int[l] + (w_dev[l] + w_q[l]);
      scratch.tet_dvol[tl] = dvol[l];
    }
  }
  if (averaged || mat.eos == EosKind::tillotson) {  // the pressure later, or cell by cell
    for (int l = 0; l < count; ++l) {
      const std::size_t tl = t[l];
      if (eroding[l]) block.eroding.push_back(static_cast<Index>(tl));
      if (averaged) continue;
      CellKinematics c;
      copy_kinematics(k, l, c);
      cell_pressure(static_cast<Index>(tl), mat, c, w_dev[l], w_q[l], dvol[l], options, st,
                    &scratch.tet_force[4 * tl], block);
    }
    return true;
  }
  // The cell's own pressure (point_pressure): E^{n+1} = E + W_dev − ½ (pⁿ + p^{n+1}) ΔV + W_q
  // with p^{n+1} = A(μ) + B E^{n+1}/V0 (solve_energy, implicit_energy), at the end volume.
  double mu[kLanes], eos_b[kLanes], eos_da[kLanes], e_new[kLanes], p_new[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    const double m = vol0[l] / vol_end[l] - 1.0;
    double a;
    eos_in_lane(mat, m, a, eos_b[l], eos_da[l]);
    const double e = e_int[l] + w_dev[l];
    const double solved =
        (e - 0.5 * (p_old[l] + a) * dvol[l] + w_q[l]) / (1.0 + 0.5 * eos_b[l] * dvol[l] / vol0[l]);
    e_new[l] = solved;
    p_new[l] = a + eos_b[l] * solved / vol0[l];
    mu[l] = m;
  }
  // Failure (the pressure a failed cell carries, its energy with it) and the shear modulus of
  // the new state, cell by cell.
  double shear_end[kLanes];
  for (int l = 0; l < kLanes; ++l) shear_end[l] = mat.shear_modulus;
  for (int l = 0; l < count; ++l) {
    const Index ti = static_cast<Index>(t[l]);
    if (options.fracture) {
      const double carried = fail(mat, vol_end[l], p_new[l], tet_point(st, ti));
      if (carried != p_new[l]) {
        p_new[l] = carried;
        e_new[l] = e_int[l] + w_dev[l] - 0.5 * (p_old[l] + p_new[l]) * dvol[l] + w_q[l];
      }
    }
    if (sg) shear_end[l] = shear_modulus_at(mat, p_new[l], temperature[l], 1.0 + mu[l]);
  }
  double s_end[6][kLanes];
  for (int l = 0; l < kLanes; ++l) {
    const Sym6& sl = st.s[t[l < count ? l : 0]];  // after failure, which may drop it
    for (int i = 0; i < 6; ++i) s_end[i][l] = sl[i];
  }
  // The sound speed, the forces on the end geometry, the step limit.
  double sound2_end[kLanes], f[4][3][kLanes], dt2[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    sound2_end[l] = sound2_in_lane(mat, mu[l], p_new[l], eos_b[l], eos_da[l], shear_end[l]);
    forces_in_lane(l, k.ge, s_end, p_new[l] + q_new[l], sound2_end[l], trace[l], options, f, dt2);
  }
  for (int l = 0; l < count; ++l) {
    const std::size_t tl = t[l];
    if (eroding[l]) block.eroding.push_back(static_cast<Index>(tl));
    st.e_int[tl] = e_new[l];
    st.p[tl] = p_new[l];
    st.sound2[tl] = sound2_end[l];
    store_forces(l, tl, f, dt2[l], options, scratch, block);
  }
  return true;
}

// Pass 3 in lanes: averaged_cell_pressure for the cells tets[t[l]], l < count, of one
// material whose equation of state is linear or Mie–Grüneisen, none of them failed (those, and
// Tillotson's, take averaged_cell_pressure). The cells' data are gathered into a structure of
// arrays, every quantity is computed lane by lane with exactly the operations, in the order, of
// the scalar path (eos_terms, the stabilization, sound_speed2, tet_geometry, tet_forces,
// stable_step2), so that each lane's doubles are the scalar path's bit for bit, and the results
// are scattered back. Failure (fail) and Steinberg–Guinan's shear modulus run cell by cell
// between the lanes' stages, as scalar calls. The step limits are reduced in the cells' order:
// the same limit, critical cell and eroding list as the scalar path. Lanes past count repeat
// the first cell. Returns false, having written nothing, where a cell's end geometry is
// inverted or not finite: the caller then takes the scalar path, which reports it.
[[gnu::always_inline]] inline bool lane_averaged_pressure(
    const std::size_t* t, int count, const std::vector<Tet>& tets, const Material& mat,
    const ElementOptions& options, State& st, ElementScratch& scratch, ForceResult& block) {
  // Gather.
  double e[3][3][kLanes];
  double vol0[kLanes], vol[kLanes], p_new[kLanes], jbar[kLanes], p_old[kLanes], dvol[kLanes],
      e_int[kLanes], q[kLanes], trace[kLanes], s[6][kLanes], shear[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    const std::size_t tl = t[l < count ? l : 0];
    const Tet& k = tets[tl];
    const Vec3& x0 = st.x[k[0]];
    for (int i = 0; i < 3; ++i)
      for (int d = 0; d < 3; ++d) e[i][d][l] = st.x[k[i + 1]][d] - x0[d];
    p_new[l] = 0.25 * (scratch.pressure[k[0]] + scratch.pressure[k[1]] + scratch.pressure[k[2]] +
                       scratch.pressure[k[3]]);
    jbar[l] = 0.25 * (scratch.node_j[k[0]] + scratch.node_j[k[1]] + scratch.node_j[k[2]] +
                      scratch.node_j[k[3]]);
    vol0[l] = st.vol0[tl];
    vol[l] = st.vol[tl];
    p_old[l] = st.p[tl];
    dvol[l] = scratch.tet_dvol[tl];
    e_int[l] = st.e_int[tl];
    q[l] = st.q[tl];
    trace[l] = st.trace_d[tl];
    shear[l] = mat.shear_modulus;
  }
  LaneGeometry g;
  lane_geometry(e, g);
  for (int l = 0; l < count; ++l)
    if (!std::isfinite(g.vol[l]) || !(g.vol[l] > 0.0)) return false;
  // The stabilization α K (J̄ − J) / J; eos_terms' B and ∂A/∂μ (the pressure is the nodes').
  double mu[kLanes], eos_b[kLanes], eos_da[kLanes];
  const double stab = options.anp_stabilization;
  for (int l = 0; l < kLanes; ++l) {
    const double m = vol0[l] / vol[l] - 1.0, j = vol[l] / vol0[l];
    const double stabilized = p_new[l] + stab * mat.bulk_modulus * (jbar[l] - j) / j;
    p_new[l] = stab > 0.0 ? stabilized : p_new[l];
    double a;
    eos_in_lane(mat, m, a, eos_b[l], eos_da[l]);
    mu[l] = m;
  }
  // Failure, and the shear modulus of the new state (Steinberg–Guinan's G(P, T)), cell by cell.
  for (int l = 0; l < count; ++l) {
    const Index ti = static_cast<Index>(t[l]);
    if (options.fracture) p_new[l] = fail(mat, vol[l], p_new[l], tet_point(st, ti));
    if (mat.strength == StrengthModel::steinberg_guinan)
      shear[l] = shear_modulus_at(mat, p_new[l], st.temperature[ti], 1.0 + mu[l]);
  }
  for (int l = 0; l < kLanes; ++l) {
    const Sym6& sl = st.s[t[l < count ? l : 0]];  // after failure, which may drop it
    for (int c = 0; c < 6; ++c) s[c][l] = sl[c];
  }
  // The energy, the sound speed (sound_speed2, bulk_stiffness), the stress the forces carry
  // (σ/3), tet_forces' f_i = (σ/3) a_i, f_0 = −(f_1 + f_2 + f_3), and stable_step2.
  double sound2[kLanes], f[4][3][kLanes], dt2[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    e_int[l] = e_int[l] - 0.5 * (p_old[l] + p_new[l]) * dvol[l];
    sound2[l] = sound2_in_lane(mat, mu[l], p_new[l], eos_b[l], eos_da[l], shear[l]);
    forces_in_lane(l, g, s, p_new[l] + q[l], sound2[l], trace[l], options, f, dt2);
  }
  // Scatter, and the step limits in the cells' order.
  for (int l = 0; l < count; ++l) {
    const std::size_t tl = t[l];
    st.e_int[tl] = e_int[l];
    st.p[tl] = p_new[l];
    st.sound2[tl] = sound2[l];
    store_forces(l, tl, f, dt2[l], options, scratch, block);
  }
  return true;
}

// The lanes' copies, one per instruction set: the same always-inlined bodies compiled for
// AVX-512 (the eight lanes in one register), AVX2 (four doubles a register) and SSE2 (two; every
// x86-64; the generic copy elsewhere). None contracts a product and a sum (element.cpp is
// compiled with -ffp-contract=off), so each gives the scalar path's doubles; the widest the
// processor runs is chosen when the program starts, and a test runs each (set_element_lanes).
struct LaneCopy {
  void (*kinematics)(const std::size_t*, int, const std::vector<Tet>&, double, const State&,
                     CellKinematics*);
  bool (*cells)(const std::size_t*, int, const std::vector<Tet>&, const Material&,
                const ElementOptions&, double, State&, ElementScratch&, ForceResult&);
  bool (*averaged)(const std::size_t*, int, const std::vector<Tet>&, const Material&,
                   const ElementOptions&, State&, ElementScratch&, ForceResult&);
};

#define TC_LANE_COPY(NAME, TARGET)                                                             \
  TARGET void NAME##_kinematics(const std::size_t* t, int count, const std::vector<Tet>& tets, \
                                double tau, const State& st, CellKinematics* c) {              \
    lane_kinematics(t, count, tets, tau, st, c);                                               \
  }                                                                                            \
  TARGET bool NAME##_cells(const std::size_t* t, int count, const std::vector<Tet>& tets,      \
                           const Material& mat, const ElementOptions& options, double tau,     \
                           State& st, ElementScratch& scratch, ForceResult& block) {           \
    return lane_cells(t, count, tets, mat, options, tau, st, scratch, block);                  \
  }                                                                                            \
  TARGET bool NAME##_averaged(const std::size_t* t, int count, const std::vector<Tet>& tets,   \
                              const Material& mat, const ElementOptions& options, State& st,   \
                              ElementScratch& scratch, ForceResult& block) {                   \
    return lane_averaged_pressure(t, count, tets, mat, options, st, scratch, block);           \
  }                                                                                            \
  constexpr LaneCopy NAME{NAME##_kinematics, NAME##_cells, NAME##_averaged};

TC_LANE_COPY(sse2_lanes, )
TC_LANE_COPY(avx2_lanes, TC_TARGET_AVX2)
TC_LANE_COPY(avx512_lanes, TC_TARGET_AVX512)
#undef TC_LANE_COPY

std::atomic<Lanes> element_lanes{widest_lanes()};

// The copy that runs, or nullptr for the scalar path.
const LaneCopy* lane_copy(Lanes lanes) {
  return copy_for<const LaneCopy*>(lanes, nullptr, &sse2_lanes, &avx2_lanes, &avx512_lanes);
}

}  // namespace

Lanes set_element_lanes(Lanes lanes) {
  return element_lanes.exchange(runnable_lanes(lanes, "element"));
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
  const LaneCopy* lanes = lane_copy(element_lanes.load(std::memory_order_relaxed));
  std::vector<ForceResult> blocks = block_results(mine.size());
  ForceResult forces = collective_pass(scratch, blocks, [&] {
    parallel::for_blocks(mine.size(), [&](std::size_t blk, std::size_t begin, std::size_t end) {
      if (!lanes) {
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
      // The cells kLanes at a time: their kinematics in lanes, each cell's checks, then their
      // material update in lanes where they share a material (else cell by cell, in order).
      std::size_t lane_tet[kLanes];
      CellKinematics c[kLanes];
      for (std::size_t i = begin; i < end;) {
        int count = 0;
        for (; i < end && count < kLanes; ++i)
          if (st.damage[mine[i]] != Damage::particle) lane_tet[count++] = mine[i];
        if (count == 0) continue;
        const Index mi = st.tet_material[lane_tet[0]];
        bool one_material = true;
        for (int l = 1; l < count; ++l) one_material &= st.tet_material[lane_tet[l]] == mi;
        if (one_material && lanes->cells(lane_tet, count, tets, materials[mi], options, tau, st,
                                         scratch, blocks[blk]))
          continue;
        lanes->kinematics(lane_tet, count, tets, tau, st, c);
        for (int l = 0; l < count; ++l) {
          check_kinematics(static_cast<Index>(lane_tet[l]), st, c[l]);
          update_cell(lane_tet[l], c[l], materials, options, tau, st, scratch, blocks[blk]);
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
      if (!lanes) {
        for (std::size_t i = begin; i < end; ++i) {
          const std::size_t t = mine[i];
          const Index mi = st.tet_material[t];
          if (!averages_pressure(options, mi) || st.damage[t] == Damage::particle) continue;
          averaged_cell_pressure(t, tets[t], materials[mi], options, st, scratch, blocks[blk]);
        }
        return;
      }
      // Runs of up to kLanes cells of one material in lanes; a cell the lanes do not take
      // (failed, or Tillotson's) alone, after the run before it: the cells keep their order.
      std::size_t lane_tet[kLanes];
      int count = 0;
      Index lane_material = -1;
      const auto flush = [&] {
        if (count > 0 && !lanes->averaged(lane_tet, count, tets, materials[lane_material], options,
                                          st, scratch, blocks[blk]))
          for (int l = 0; l < count; ++l)  // reports the inverted cell
            averaged_cell_pressure(lane_tet[l], tets[lane_tet[l]], materials[lane_material],
                                   options, st, scratch, blocks[blk]);
        count = 0;
      };
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t t = mine[i];
        const Index mi = st.tet_material[t];
        if (!averages_pressure(options, mi) || st.damage[t] == Damage::particle) continue;
        const Material& mat = materials[mi];
        const bool in_lanes =
            mat.eos != EosKind::tillotson && !(options.fracture && st.damage[t] != Damage::intact);
        if (!in_lanes || mi != lane_material || count == kLanes) flush();
        if (!in_lanes) {
          averaged_cell_pressure(t, tets[t], mat, options, st, scratch, blocks[blk]);
          continue;
        }
        lane_material = mi;
        lane_tet[count++] = t;
      }
      flush();
    });
  });
  merge(forces, {third});
  gather_forces(mesh_nodes, scratch, st);
  if (distributed(scratch)) share_damaged(scratch, st, forces.eroding);
  return finish_forces(forces);
}

}  // namespace tc
