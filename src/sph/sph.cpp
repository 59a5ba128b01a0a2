#include "tetcontact/sph/sph.hpp"
#include "tetcontact/model/persist.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "tetcontact/element/element.hpp"
#include "tetcontact/element/material_point.hpp"
#include "tetcontact/mesh/symmetry.hpp"
#include "tetcontact/parallel/parallel.hpp"
#include "tetcontact/sph/boundary.hpp"
#include "tetcontact/sph/kernel.hpp"

namespace tc::sph {

namespace {

// A particle's pass costs microseconds, and unequally (one near the faces integrates each of
// them): blocks of 64 particles share a cloud of a few thousand evenly among the threads, where
// the default blocks of 1,024 made a handful. The results do not depend on the blocks (each
// particle's sums are its own; the step's minimum and the face terms are taken in particle
// order).
constexpr std::size_t k_particle_block = 64;

MaterialPoint particle_point(State& st, Index i) {
  ParticleMatter& pm = st.sph;
  return {pm.s[i],
          pm.p[i],
          pm.q[i],
          st.particle_energy[i],
          pm.eps_p[i],
          pm.ductile[i],
          pm.ductile_floor[i],
          pm.w_plastic[i],
          pm.w_viscous[i],
          pm.sound2[i],
          pm.trace_d[i],
          pm.temperature[i],
          pm.vol[i],
          pm.vol0[i],
          pm.damage[i]};
}

// Whether a set of planes holds two of one axis (their joint image is a translation far beyond
// any kernel's reach: not a neighbour).
bool same_axis_twice(const std::vector<MirrorPlane>& planes, unsigned mask) {
  unsigned axes = 0;
  for (std::size_t k = 0; k < planes.size(); ++k) {
    if (!(mask >> k & 1u)) continue;
    const unsigned bit = 1u << planes[k].axis;
    if (axes & bit) return true;
    axes |= bit;
  }
  return false;
}

// A cell stretched past its reference volume (a loosened, destroyed cell carries no tension and
// may have been drawn out to many times its volume) is, as a particle, its material at the
// volume where its pressure falls to zero at its energy E, if that is less, and no more than
// twice V0: on the Mie–Grüneisen's (or linear) branch of expansion p = k μ + B E/V0 = 0 at
// μ = −B E/(k V0) (V0 for a linear EOS); with Tillotson's, its volume if the pressure there is
// not tensile, else the zero between it and V0 by Newton's iteration kept within the bracket.
// A hot Tillotson state is a gas with no such volume: it stops at twice V0 (a destroyed
// particle carries no pressure once loosened, so nothing else would hold its density: at 1e14
// V0 the EOS's floor of stiffness gives a sound speed of 1.9e9 m/s and a step of 3e-14 s). A
// state below its reference energy keeps V0 (its pressure is tensile at any expansion). Its
// pressure there is the cell's (none while it is loosened), so the particle starts without a
// kick.
double particle_volume(const Material& m, double vol, double vol0, double energy) {
  if (!(vol > vol0)) return vol;
  if (m.eos == EosKind::tillotson) {
    const double e = energy / vol0;
    if (!(e > 0.0)) return vol0;
    double lo = std::max(vol0 / vol - 1.0, -0.5), hi = 0.0;
    if (eos_pressure(m, lo, e) >= 0.0) return lo > -0.5 ? vol : 2.0 * vol0;
    double mu = 0.5 * lo;  // p(lo) < 0 ≤ p(hi) for E ≥ 0
    for (int k = 0; k < 60; ++k) {
      const EosTerms t = eos_terms(m, mu, e);
      const double p = t.a + t.b * e;
      if (p == 0.0) break;
      (p < 0.0 ? lo : hi) = mu;
      double next = t.da_dmu > 0.0 ? mu - p / t.da_dmu : lo;
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      const bool done = std::abs(next - mu) < 1e-14;
      mu = next;
      if (done) break;
    }
    return std::min(vol, vol0 / (1.0 + mu));
  }
  const EosTerms t = eos_terms(m, -1e-12);  // the branch of expansion: A = k μ
  const double mu = std::clamp(-t.b * energy / (t.da_dmu * vol0), -0.5, 0.0);
  return std::min(vol, vol0 / (1.0 + mu));
}

// A compressed cell is, as a particle, its material at the volume where its pressure at its
// energy is the cell's pressure p_cell, the one the forces last took from it, if that volume is
// larger than the cell's. Under the average nodal pressure a cell's pressure is its nodes' mean
// and its energy follows that pressure's work, so a cell crushed alone reaches a volume whose
// own EOS pressure is far above its neighbours' (on a Whipple shot a sphere's cell held 80 GPa
// at V/V0 = 0.46; cells crushed like it, made particles at their own volumes, read 163–455 GPa
// from their EOS, expanded at once, and one left at 3.6 km/s against the shot with
// −38 MJ/kg). On the bracket [V, 2 V0] the pressure falls with the volume; a bracket whose far
// end still holds more than p_cell gives 2 V0.
double compressed_volume(const Material& m, double vol, double vol0, double energy, double p_cell) {
  const double e = energy / vol0;
  const auto excess = [&](double mu) { return eos_pressure(m, mu, e) - p_cell; };
  double hi = vol0 / vol - 1.0;  // the cell's μ: excess(hi) > 0, else the cell's volume
  if (!(excess(hi) > 0.0)) return vol;
  double lo = -0.5;
  if (excess(lo) > 0.0) return 2.0 * vol0;
  for (int k = 0; k < 200 && hi - lo > 1e-13 * (1.0 + std::abs(hi)); ++k) {
    const double mid = 0.5 * (lo + hi);
    (excess(mid) > 0.0 ? hi : lo) = mid;
  }
  return vol0 / (1.0 + hi);
}

// The points of particle i after point k: the particle, then its images (n + [begin, end)
// of ghost_begin); `points` after the last.
std::size_t next_image(std::size_t n, const std::vector<Index>& ghost_begin, std::size_t points,
                       std::size_t i, std::size_t k) {
  const std::size_t first = n + static_cast<std::size_t>(ghost_begin[i]);
  const std::size_t last = n + static_cast<std::size_t>(ghost_begin[i + 1]);
  const std::size_t next = k < n ? first : k + 1;
  return next < last ? next : points;
}

// Whether a point (velocity v) and a face meet: they approach (at the face's centroid velocity)
// or the point presses on it (n·σ n < 0).
bool meets(const Vec3& v, const std::vector<Vec3>& node_v, const Face& f, const Vec3& n,
           double normal_stress) {
  const Vec3 vf = (node_v[f[0]] + node_v[f[1]] + node_v[f[2]]) / 3.0;
  return (v - vf).dot(n) < 0.0 || normal_stress < 0.0;
}

// The shapes of the faces a pass meets (those in `list`), each once, with its nodes at pos(v):
// shape[slot[f]] for face f. A face is met by many particles: its normal, edges and area are
// the same for each.
struct FaceShapes {
  std::vector<Index> slot;  // per face: its shape, or −1
  std::vector<FaceShape> shape;
  const FaceShape& of(Index f) const {
    return shape[static_cast<std::size_t>(slot[static_cast<std::size_t>(f)])];
  }
};
template <class Position>
FaceShapes face_shapes(const std::vector<Face>& faces, const std::vector<Index>& list,
                       Position&& pos) {
  FaceShapes out;
  out.slot.assign(faces.size(), -1);
  std::vector<Index> met;
  for (const Index f : list)
    if (out.slot[static_cast<std::size_t>(f)] < 0) {
      out.slot[static_cast<std::size_t>(f)] = static_cast<Index>(met.size());
      met.push_back(f);
    }
  out.shape.resize(met.size());
  parallel::for_each(met.size(), [&](std::size_t u) {
    const Face& q = faces[static_cast<std::size_t>(met[u])];
    out.shape[u] = face_shape(pos(q[0]), pos(q[1]), pos(q[2]));
  });
  return out;
}

[[noreturn]] void bad_particle(Index i, const char* what, double value) {
  std::ostringstream os;
  os << "SPH particle " << i << ": " << what << " " << value;
  throw RunFailure(os.str());
}

}  // namespace

std::vector<SymmetryPlane> symmetry_planes(const std::vector<MirrorPlane>& planes) {
  std::vector<SymmetryPlane> out;
  for (const MirrorPlane& p : planes) out.push_back({p.axis, p.at});
  return out;
}

// σ' = R σ R with R = diag(r), r the signs the axes take: σ'_ab = r_a r_b σ_ab.
Sym6 mirror_stress(Sym6 s, const std::vector<SymmetryPlane>& planes, unsigned mask) {
  const Vec3 r = mirror_direction(Vec3(1.0, 1.0, 1.0), planes, static_cast<int>(mask));
  s[3] *= r[0] * r[1];
  s[4] *= r[1] * r[2];
  s[5] *= r[0] * r[2];
  return s;
}

// Each particle's candidates (the pairs' other particles), ascending: the pairs sorted by (i, j)
// give particle i its j < i from the blocks before its own, then its j > i.
std::pair<std::vector<Index>, std::vector<Index>> candidates_by_particle(
    std::size_t n, std::span<const std::pair<Index, Index>> pairs) {
  if (!std::is_sorted(pairs.begin(), pairs.end()))
    throw std::logic_error("SPH candidates: the pairs are not sorted");
  std::vector<Index> begin(n + 1, 0), list(2 * pairs.size());
  for (const auto& [i, j] : pairs) {
    if (!(i >= 0 && i < j && static_cast<std::size_t>(j) < n))
      throw std::logic_error("SPH candidates: a pair not (i, j) with i < j < particles");
    ++begin[static_cast<std::size_t>(i) + 1];
    ++begin[static_cast<std::size_t>(j) + 1];
  }
  for (std::size_t i = 0; i < n; ++i) begin[i + 1] += begin[i];
  std::vector<Index> next(begin.begin(), begin.end() - 1);
  for (const auto& [i, j] : pairs) {
    list[static_cast<std::size_t>(next[i]++)] = j;
    list[static_cast<std::size_t>(next[j]++)] = i;
  }
  return {std::move(begin), std::move(list)};
}

// The mirror images' pairs come from the particles' own: for planes whose side holds both
// points, each coordinate of an image differs from a point's by |a + b| ≥ |a − b| (a, b the two
// distances from the plane, of one sign), so an image is no nearer than its particle.
Neighbours find_neighbours(const std::vector<Vec3>& x, const std::vector<double>& h,
                           const std::vector<MirrorPlane>& planes, double reach,
                           std::span<const std::pair<Index, Index>> pairs) {
  Neighbours nb;
  const std::size_t n = x.size();
  nb.particles = static_cast<Index>(n);
  nb.begin.assign(n + 1, 0);
  if (n == 0) return nb;
  const double hmax = *std::max_element(h.begin(), h.end());
  const double radius = reach * k_support * hmax;
  const std::vector<SymmetryPlane> symmetry = symmetry_planes(planes);
  // The points: the particles, then the images of those within reach of every plane of a set,
  // each particle's together.
  std::vector<Vec3> pts(x);
  std::vector<Index> ghosts(n + 1, 0);  // per particle: its images n + [ghosts[i], ghosts[i + 1])
  for (std::size_t i = 0; i < n; ++i) {
    if (!x[i].allFinite()) bad_particle(static_cast<Index>(i), "position not finite:", x[i].norm());
    for (unsigned mask = 1; mask < (1u << planes.size()); ++mask) {
      if (same_axis_twice(planes, mask)) continue;
      bool near = true;
      for (std::size_t k = 0; k < planes.size() && near; ++k)
        if (mask >> k & 1u) near = planes[k].side * (x[i][planes[k].axis] - planes[k].at) < radius;
      if (!near) continue;
      nb.ghost_source.push_back(static_cast<Index>(i));
      nb.ghost_planes.push_back(mask);
      pts.push_back(mirror_image(x[i], symmetry, static_cast<int>(mask)));
    }
    ghosts[i + 1] = static_cast<Index>(nb.ghost_source.size());
  }
  const auto [cand_begin, cand] = candidates_by_particle(n, pairs);
  std::vector<std::vector<Index>> lists(n);
  parallel::for_each(
      n,
      [&](std::size_t i) {
        std::vector<Index>& out = lists[i];
        const auto within = [&](std::size_t k, std::size_t src) {
          return (x[i] - pts[k]).norm() < reach * k_support * 0.5 * (h[i] + h[src]);
        };
        for (Index e = cand_begin[i]; e < cand_begin[i + 1]; ++e)
          if (within(static_cast<std::size_t>(cand[e]), static_cast<std::size_t>(cand[e])))
            out.push_back(cand[e]);
        // The images of the particle itself and of its candidates, in ascending source order.
        const auto images_of = [&](std::size_t src) {
          for (Index g = ghosts[src]; g < ghosts[src + 1]; ++g)
            if (within(n + static_cast<std::size_t>(g), src))
              out.push_back(static_cast<Index>(n) + g);
        };
        bool self = false;
        for (Index e = cand_begin[i]; e < cand_begin[i + 1]; ++e) {
          const std::size_t j = static_cast<std::size_t>(cand[e]);
          if (!self && j > i) {
            images_of(i);
            self = true;
          }
          images_of(j);
        }
        if (!self) images_of(i);
      },
      k_particle_block);
  for (std::size_t i = 0; i < n; ++i)
    nb.begin[i + 1] = nb.begin[i] + static_cast<Index>(lists[i].size());
  nb.list.reserve(static_cast<std::size_t>(nb.begin[n]));
  for (const std::vector<Index>& l : lists) nb.list.insert(nb.list.end(), l.begin(), l.end());
  return nb;
}

void Stage::find(const State& st, const std::vector<Face>& faces, const Candidates& candidates) {
  const std::size_t n = static_cast<std::size_t>(st.sph.size());
  std::vector<Vec3> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = st.x[st.first_particle + i];
  neighbours_ = find_neighbours(x, st.sph.h, planes_, options_.reach, candidates.pairs);
  const Neighbours& nb = neighbours_;
  // The images of a particle are listed together, in particle order.
  ghost_begin_.assign(n + 1, 0);
  for (Index src : nb.ghost_source) ++ghost_begin_[static_cast<std::size_t>(src) + 1];
  for (std::size_t i = 0; i < n; ++i) ghost_begin_[i + 1] += ghost_begin_[i];
  const std::size_t points = n + nb.ghost_source.size();
  face_begin_.assign(points + 1, 0);
  face_list_.clear();
  if (!options_.faces || faces.empty() || n == 0) return;
  // The faces within reach × 2 h of each point (particle or image), of its particle's candidate
  // faces (an image is no nearer than its particle to a face on the planes' side): by point, then
  // face.
  if (!std::is_sorted(candidates.faces.begin(), candidates.faces.end()))
    throw std::logic_error("SPH candidates: the face pairs are not sorted");
  std::vector<Index> cand_begin(n + 1, 0);
  for (const auto& [i, f] : candidates.faces) {
    if (!(i >= 0 && static_cast<std::size_t>(i) < n && f >= 0 &&
          static_cast<std::size_t>(f) < faces.size()))
      throw std::logic_error("SPH candidates: a face pair out of range");
    ++cand_begin[static_cast<std::size_t>(i) + 1];
  }
  for (std::size_t i = 0; i < n; ++i) cand_begin[i + 1] += cand_begin[i];
  std::vector<std::vector<Index>> found(points);
  parallel::for_each(
      points,
      [&](std::size_t k) {
        const Index src = k < n ? static_cast<Index>(k) : nb.ghost_source[k - n];
        const Vec3 p =
            k < n ? x[k]
                  : mirror_image(x[src], symmetry_, static_cast<int>(nb.ghost_planes[k - n]));
        const double reach = options_.reach * k_support * st.sph.h[src];
        for (Index e = cand_begin[src]; e < cand_begin[src + 1]; ++e) {
          const Index f = candidates.faces[static_cast<std::size_t>(e)].second;
          const Face& q = faces[static_cast<std::size_t>(f)];
          const Vec3 lo = st.x[q[0]].cwiseMin(st.x[q[1]]).cwiseMin(st.x[q[2]]);
          const Vec3 hi = st.x[q[0]].cwiseMax(st.x[q[1]]).cwiseMax(st.x[q[2]]);
          const Vec3 gap = (lo - p).cwiseMax(p - hi).cwiseMax(Vec3::Zero());
          if (gap.norm() < reach) found[k].push_back(f);
        }
      },
      k_particle_block);
  for (std::size_t k = 0; k < points; ++k)
    face_begin_[k + 1] = face_begin_[k] + static_cast<Index>(found[k].size());
  face_list_.reserve(static_cast<std::size_t>(face_begin_[points]));
  for (const std::vector<Index>& l : found) face_list_.insert(face_list_.end(), l.begin(), l.end());
}

// The pair's ∇_i W_ij and A_ij = −Π_ij I + f_ijⁿ (R_i + R_j); μ_ij where it approaches (point k,
// of particle j, as seen from particle i at r = x_i − x_k, v_ik = dv).
Stage::PairTerms Stage::pair_terms(const ParticleMatter& pm, std::size_t i, std::size_t k, Index j,
                                   const Vec3& r, const Vec3& dv) const {
  const double alpha = options_.alpha, beta = options_.beta, expo = options_.stress_exponent;
  PairTerms t{Vec3::Zero(), Sym6{0, 0, 0, 0, 0, 0}, 0.0, false};
  const double hij = 0.5 * (pm.h[i] + pm.h[j]);
  t.g = kernel_gradient(r, hij);
  const double vr = dv.dot(r);
  if (vr < 0.0) {
    t.mu = hij * vr / (r.squaredNorm() + 0.01 * hij * hij);
    const double cbar = 0.5 * (std::sqrt(pm.sound2[i]) + std::sqrt(pm.sound2[j]));
    const double rhobar = 0.5 * (pm.rho[i] + pm.rho[j]);
    const double pi = (-alpha * cbar * t.mu + beta * t.mu * t.mu) / rhobar;
    for (int c = 0; c < 3; ++c) t.a[c] -= pi;
    t.extra = true;
  }
  if (options_.artificial_stress > 0.0) {
    const double dp = 0.5 * (pm.spacing[i] + pm.spacing[j]);
    const double base = kernel(r.norm(), hij) / kernel(dp, hij);
    const double f = expo == 4.0 ? (base * base) * (base * base) : std::pow(base, expo);
    if (f > 0.0) {
      for (int c = 0; c < 6; ++c) t.a[c] += f * (art_[i][c] + art_[k][c]);
      t.extra = true;
    }
  }
  return t;
}

// The heat of the last forces' pairs and faces over the kick they gave, at the kick's mean
// velocity v̄ = vⁿ + ½ Δv with Δv the velocities' change actually reached (the forces' kick and
// the walls' and contacts' corrections after it): the heat is linear in the velocities, so
//   W_i = τ_v (heat_i(vⁿ) + ½ heat_i(Δv)),
// heat_i(v) = −½ Σ_j m_i m_j v_ij · A_ij ∇_i W_ij + Σ_faces coef · (v_k − Σ_v w_v v_v).
// With Δv = τ_v a (the forces' kick alone) a particle held by a wall was booked the heat of
// a motion it did not make. Before `find`: the last forces' lists, points and state.
std::vector<double> Stage::kick_heat(const State& st, double tau_kick) const {
  const ParticleMatter& pm = st.sph;
  const std::size_t n = heat_rate_.size();
  const Index fp = st.first_particle;
  const Neighbours& nb = neighbours_;
  std::vector<double> heat(n, 0.0);
  if (n == 0 || nb.particles != static_cast<Index>(n)) return heat;
  const std::size_t points = n + nb.ghost_source.size();
  std::vector<Vec3> dv(points);
  for (std::size_t i = 0; i < n; ++i) dv[i] = st.v[fp + i] - v_[i];
  for (std::size_t g = 0; g < nb.ghost_source.size(); ++g)
    dv[n + g] =
        mirror_direction(dv[nb.ghost_source[g]], symmetry_, static_cast<int>(nb.ghost_planes[g]));
  // The pairs' A_ij ∇_i W_ij as the last forces computed them (not after a restart: then again).
  const bool kept = pair_ag_.size() == nb.list.size() && pair_extra_.size() == nb.list.size();
  parallel::for_each(
      n,
      [&](std::size_t i) {
        const double mi = st.m[fp + i];
        double change = 0.0;  // heat_i(Δv)
        for (Index e = nb.begin[i]; e < nb.begin[i + 1]; ++e) {
          const std::size_t k = static_cast<std::size_t>(nb.list[e]);
          const Index j = k < n ? static_cast<Index>(k) : nb.ghost_source[k - n];
          const std::size_t at = static_cast<std::size_t>(e);
          if (kept) {  // the forces' A_ij ∇_i W_ij
            if (!pair_extra_[at]) continue;
            change -= 0.5 * mi * st.m[fp + j] * (dv[i] - dv[k]).dot(pair_ag_[at]);
            continue;
          }
          const PairTerms t = pair_terms(pm, i, k, j, x_[i] - x_[k], v_[i] - v_[k]);
          if (!t.extra) continue;
          change -= 0.5 * mi * st.m[fp + j] * (dv[i] - dv[k]).dot(to_mat3(t.a) * t.g);
        }
        for (Index e = term_begin_[i]; e < term_begin_[i + 1]; ++e) {
          const FaceTerm& t = face_terms_[static_cast<std::size_t>(e)];
          const Vec3 dk = mirror_direction(dv[i], symmetry_, static_cast<int>(t.mask));
          Vec3 vf = Vec3::Zero();
          for (int v = 0; v < 3; ++v) vf += t.w[v] * st.v[t.face[v]];
          change += t.coef.dot(dk - (vf - t.v_face));
        }
        heat[i] = tau_kick * (heat_rate_[i] + 0.5 * change);
      },
      k_particle_block);
  return heat;
}

void Stage::update(const std::vector<Material>& materials, double tau, double tau_kick, State& st,
                   const std::vector<Face>& faces, const Candidates& candidates) {
  ParticleMatter& pm = st.sph;
  const std::size_t n = static_cast<std::size_t>(pm.size());
  const Index fp = st.first_particle;
  const std::vector<double> pair_heat = kick_heat(st, tau_kick);
  find(st, faces, candidates);
  fresh_ = true;
  const Neighbours& nb = neighbours_;
  // The points at mid-step, x^{n+1} − τ/2 U^{n+1/2}, with their velocities.
  const std::size_t points = n + nb.ghost_source.size();
  x_.resize(points);
  v_.resize(points);
  for (std::size_t i = 0; i < n; ++i) {
    v_[i] = st.v[fp + i];
    x_[i] = st.x[fp + i] - 0.5 * tau * v_[i];
  }
  for (std::size_t g = 0; g < nb.ghost_source.size(); ++g) {
    const Index i = nb.ghost_source[g];
    const int mask = static_cast<int>(nb.ghost_planes[g]);
    x_[n + g] = mirror_image(x_[i], symmetry_, mask);
    v_[n + g] = mirror_direction(v_[i], symmetry_, mask);
  }
  // The faces at mid-step, x − τ/2 U.
  const FaceShapes shapes =
      face_shapes(faces, face_list_, [&](Index v) { return Vec3(st.x[v] - 0.5 * tau * st.v[v]); });
  parallel::for_each(
      n,
      [&](std::size_t i) {
        // L_i = −(1/ρ_i) Σ_j m_j v_ij ⊗ ∇_i W_ij.
        // B_i = −(1/ρ_i) Σ_j m_j x_ij ⊗ ∇_i W_ij, the same sum of a linear field's positions.
        Mat3 L = Mat3::Zero(), B = Mat3::Zero();
        for (Index e = nb.begin[i]; e < nb.begin[i + 1]; ++e) {
          const std::size_t k = static_cast<std::size_t>(nb.list[e]);
          const Index src = k < n ? static_cast<Index>(k) : nb.ghost_source[k - n];
          const Vec3 g = kernel_gradient(x_[i] - x_[k], 0.5 * (pm.h[i] + pm.h[src]));
          const double mj = st.m[fp + src];
          L += (mj * (v_[i] - v_[k])) * g.transpose();
          B += (mj * (x_[i] - x_[k])) * g.transpose();
        }
        const double scale = -1.0 / pm.rho[i];
        L *= scale;
        B *= scale;
        Mat3 L_faces = Mat3::Zero(), B_faces = Mat3::Zero();
        // The faces met by the particle and its images: L_i += v_if ⊗ n Φ (an image's term
        // reflected back, R L' R), at the faces' mid-step positions.
        const Mat3 sigma = to_mat3(pm.s[i]) - (pm.p[i] + pm.q[i]) * Mat3::Identity();
        bool met = false;  // a face stands in for neighbours
        for (std::size_t k = i; k < points; k = next_image(n, ghost_begin_, points, i, k)) {
          const unsigned mask = k < n ? 0u : nb.ghost_planes[k - n];
          const Vec3 r = mirror_direction(Vec3(1.0, 1.0, 1.0), symmetry_, static_cast<int>(mask));
          const Mat3 sk = r.asDiagonal() * sigma * r.asDiagonal();
          for (Index e = face_begin_[k]; e < face_begin_[k + 1]; ++e) {
            const Face& f = faces[static_cast<std::size_t>(face_list_[e])];
            const FaceShape& shape = shapes.of(face_list_[e]);
            const std::array<Vec3, 3>& xf = shape.corner;
            const Vec3& nrm = shape.normal;
            if (!nrm.allFinite() || !meets(v_[k], st.v, f, nrm, nrm.dot(sk * nrm))) continue;
            const FaceKernel fk = face_kernel(x_[k], shape, pm.h[i]);
            if (!(fk.phi > 0.0)) continue;
            const Vec3 dv =
                v_[k] - (fk.w[0] * st.v[f[0]] + fk.w[1] * st.v[f[1]] + fk.w[2] * st.v[f[2]]);
            const Vec3 dx = x_[k] - (fk.w[0] * xf[0] + fk.w[1] * xf[1] + fk.w[2] * xf[2]);
            const Mat3 lk = (fk.phi * dv) * nrm.transpose(), bk = (fk.phi * dx) * nrm.transpose();
            L_faces += r.asDiagonal() * lk * r.asDiagonal();
            B_faces += r.asDiagonal() * bk * r.asDiagonal();
            met = true;
          }
        }
        // The pairs' sum at the mid-step density, 1/ρ^{n+1/2} = V^{n+1/2}/m: its work
        // V^{n+1/2} σ : L is then m_i m_j σ_i/ρ_i² · v_ij ⊗ ∇W at mid-step, the forces' at both
        // ends averaged (with 1/ρⁿ a compression did more work on the particles than the forces did
        // on their motion, 1.6e-3 of the energy over 38 steps of two rods of particles meeting).
        // V^{n+1/2} = V/(1 − ½τ tr L) depends on it: a fixed point, three passes.
        {
          const double a = 0.5 * tau * L.trace(), b = 0.5 * tau * L_faces.trace();
          double ratio = 1.0;
          for (int pass = 0; pass < 3; ++pass) {
            const double half = ratio * a + b;
            if (!(half < 0.5 && half > -0.5)) break;
            ratio = 1.0 / (1.0 - half);
          }
          L = ratio * L + L_faces;
          B = ratio * B + B_faces;
        }
        // Where faces stand in for neighbours, they give the body's velocity at the face, not its
        // gradient beyond it: the gradient is corrected there so that a linear field's is exact
        // (L B⁻¹; B well conditioned, else the plain sum), and the volume and the deviator follow
        // the corrected rate. The work is taken with the plain sum's rate, whose work is the
        // forces' to the bit: the corrected rate's work is not theirs (it broke the balance by
        // 1e-2 on a Whipple shot whose intact crushed cells became particles).
        PointMotion c, plain;
        double Lr[3][3];
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) Lr[a][b] = L(a, b);
        set_rates(Lr, plain);
        c = plain;
        if (met) {
          const Mat3 inv = B.inverse();
          if (inv.allFinite() && inv.norm() < 4.0) {
            const Mat3 lc = L * inv;
            for (int a = 0; a < 3; ++a)
              for (int b = 0; b < 3; ++b) Lr[a][b] = lc(a, b);
            set_rates(Lr, c);
          }
        }
        // dV/dt = V tr D by the trapezoid: ΔV = τ tr D V^{n+1/2}. A failed particle in expansion
        // opens cracks instead: its solid grows only up to the volume where its pressure at its
        // energy is zero (particle_volume), beyond which the particles part as fragments (their
        // continuity would otherwise read the cloud's spreading as the solid's, and its density
        // fell to a thousandth of ρ0 in a Whipple shot).
        const double half = 0.5 * tau * c.trace;
        bool failed = options_.fracture && pm.damage[i] != Damage::intact;
        const Material& mat = materials[pm.material[i]];
        // An intact particle that would grow past 2 V0 fails, its solid then held as a failed
        // one's: a hot expanded state (Mie–Grüneisen's Γ0 E cancelling K μ) carries almost no
        // tension to spall it, and left intact one swelled from 100 V0 to 6,700 V0 in 25 steps.
        if (options_.fracture && !failed && half > 0.0 &&
            !(pm.vol[i] * (1.0 + half) < 2.0 * pm.vol0[i] * (1.0 - half))) {
          pm.damage[i] = Damage::damaged;
          pm.s[i] = Sym6{0, 0, 0, 0, 0, 0};
          failed = true;
        }
        if (failed && half > 0.0) {
          const double grown = half < 1.0 ? pm.vol[i] * (1.0 + half) / (1.0 - half)
                                          : std::numeric_limits<double>::infinity();
          const double solid = particle_volume(mat, grown, pm.vol0[i], st.particle_energy[i]);
          c.vol_end = std::max(pm.vol[i], solid);
        } else if (!(half < 1.0) || !(half > -1.0)) {
          std::ostringstream os;
          os << "SPH particle " << i << " (node " << fp + static_cast<Index>(i) << " at "
             << st.x[fp + i].transpose() << " m): its volume would change by more than it has in "
             << "one step (τ tr D / 2 = " << half << "; h " << pm.h[i] << " m, density "
             << pm.rho[i] << " kg/m^3, " << nb.begin[i + 1] - nb.begin[i] << " neighbours)";
          throw RunFailure(os.str());
        } else {
          c.vol_end = pm.vol[i] * (1.0 + half) / (1.0 - half);
        }
        c.vol_mid = 0.5 * (pm.vol[i] + c.vol_end);
        const MaterialPoint pt = particle_point(st, static_cast<Index>(i));
        const double mass = st.m[fp + i];
        const double vol_start = pm.vol[i];
        double w_p = 0.0, dvol = 0.0;
        bool eroding = false;
        const double w_dev =
            deviator_work(mat, c, plain.d, mass / c.vol_mid, failed, tau, pt, w_p, eroding);
        double w_q = viscous_work(mat, c, 0.0, w_p, pt, dvol);
        // The pressure's work over the plain rate's volume change, where it differs: the volume
        // the EOS reads is the corrected one's, the energy the forces'.
        const double half_plain = 0.5 * tau * plain.trace;
        if (c.trace != plain.trace && !(failed && half > 0.0) && half_plain < 1.0 &&
            half_plain > -1.0)
          dvol = vol_start * 2.0 * half_plain / (1.0 - half_plain);
        // The pair heat of the last forces over the kick that applied them.
        if (i < pair_heat.size()) {  // not for a particle made since the last forces
          const double w_pair = pair_heat[i];
          pt.w_viscous += w_pair;
          if (mat.thermal()) pt.temperature += w_pair / (mat.density * pt.vol0 * mat.specific_heat);
          w_q += w_pair;
        }
        point_pressure(mat, w_dev, w_q, dvol, options_.fracture, pt);
        // Ductile failure or the strain limit: the particle keeps its pressure in compression only.
        if (eroding && options_.fracture && pm.damage[i] == Damage::intact) {
          pm.damage[i] = Damage::damaged;
          pm.s[i] = Sym6{0, 0, 0, 0, 0, 0};
          if (pm.p[i] < 0.0) pm.p[i] = 0.0;
        }
        pm.rho[i] = mass / pm.vol[i];
        if (!std::isfinite(pm.p[i]) || !std::isfinite(st.particle_energy[i]))
          bad_particle(static_cast<Index>(i), "pressure not finite:", pm.p[i]);
      },
      k_particle_block);
}

StepLimit Stage::forces(State& st, const std::vector<Face>& faces, const Candidates& candidates) {
  ParticleMatter& pm = st.sph;
  const std::size_t n = static_cast<std::size_t>(pm.size());
  const Index fp = st.first_particle;
  if (!fresh_ || neighbours_.particles != static_cast<Index>(n)) find(st, faces, candidates);
  fresh_ = false;
  const Neighbours& nb = neighbours_;
  const std::size_t points = n + nb.ghost_source.size();
  const auto source = [&](std::size_t k) {
    return k < n ? static_cast<Index>(k) : nb.ghost_source[k - n];
  };
  x_.resize(points);
  v_.resize(points);
  stress_.resize(points);
  art_.resize(points);
  // Per particle: σ/ρ² and the artificial stress R.
  const double eps = options_.artificial_stress;
  parallel::for_each(
      n,
      [&](std::size_t i) {
        x_[i] = st.x[fp + i];
        v_[i] = st.v[fp + i];
        const double r2 = pm.rho[i] * pm.rho[i];
        Sym6 s = pm.s[i];
        const double pq = pm.p[i] + pm.q[i];
        for (int a = 0; a < 3; ++a) s[a] -= pq;
        art_[i] = Sym6{0, 0, 0, 0, 0, 0};
        if (eps > 0.0) {
          Eigen::SelfAdjointEigenSolver<Mat3> es;
          es.computeDirect(to_mat3(s));
          const Vec3 lam = es.eigenvalues();
          if (lam.maxCoeff() > 0.0) {
            Vec3 r = Vec3::Zero();
            for (int a = 0; a < 3; ++a)
              if (lam[a] > 0.0) r[a] = -eps * lam[a] / r2;
            const Mat3& q = es.eigenvectors();
            art_[i] = to_sym6(q * r.asDiagonal() * q.transpose());
          }
        }
        for (double& c : s) c /= r2;
        stress_[i] = s;
      },
      k_particle_block);
  for (std::size_t g = 0; g < nb.ghost_source.size(); ++g) {
    const Index i = nb.ghost_source[g];
    const unsigned mask = nb.ghost_planes[g];
    x_[n + g] = mirror_image(x_[i], symmetry_, static_cast<int>(mask));
    v_[n + g] = mirror_direction(v_[i], symmetry_, static_cast<int>(mask));
    stress_[n + g] = mirror_stress(stress_[i], symmetry_, mask);
    art_[n + g] = mirror_stress(art_[i], symmetry_, mask);
  }
  heat_rate_.assign(n, 0.0);
  plane_force_.assign(n, Vec3::Zero());
  pair_ag_.resize(nb.list.size());
  pair_extra_.resize(nb.list.size());  // each entry written by the pass below
  const double alpha = options_.alpha, beta = options_.beta;
  std::vector<StepLimit> blocks(parallel::block_count(n, k_particle_block),
                                StepLimit{std::numeric_limits<double>::infinity(), -1});
  std::vector<std::vector<FaceTerm>> block_terms(blocks.size());
  const FaceShapes shapes =
      face_shapes(faces, face_list_, [&](Index v) -> const Vec3& { return st.x[v]; });
  parallel::for_blocks(
      n,
      [&](std::size_t blk, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          const double mi = st.m[fp + i], ci = std::sqrt(pm.sound2[i]);
          Vec3 acc = Vec3::Zero(), from_images = Vec3::Zero();
          double heat = 0.0, mu_max = 0.0;
          for (Index e = nb.begin[i]; e < nb.begin[i + 1]; ++e) {
            const std::size_t k = static_cast<std::size_t>(nb.list[e]);
            const Index j = source(k);
            const Vec3 r = x_[i] - x_[k], dv = v_[i] - v_[k];
            const PairTerms t = pair_terms(pm, i, k, j, r, dv);
            const std::size_t at = static_cast<std::size_t>(e);
            pair_extra_[at] = t.extra;
            if (t.extra) pair_ag_[at] = to_mat3(t.a) * t.g;  // kept for the heat over the kick
            if (t.g.isZero(0.0)) continue;
            Sym6 sum;
            for (int c = 0; c < 6; ++c) sum[c] = stress_[i][c] + stress_[k][c] + t.a[c];
            const double mj = st.m[fp + j];
            (k < n ? acc : from_images) += mj * (to_mat3(sum) * t.g);
            if (t.extra) heat -= 0.5 * mi * mj * dv.dot(pair_ag_[at]);
            mu_max = std::max(mu_max, -t.mu);
          }
          Vec3 force = mi * (acc + from_images);
          plane_force_[i] = mi * from_images;
          // The faces met by the particle and its images (see the header): F = −m_i ρ_i Φ
          // (2 σ_i/ρ_i² − Π) n on the point, its opposite on the face's nodes; an image's force
          // reflected back onto the particle, the difference the planes' push.
          const double rho = pm.rho[i], hi = pm.h[i];
          for (std::size_t k = i; k < points; k = next_image(n, ghost_begin_, points, i, k)) {
            const unsigned mask = k < n ? 0u : nb.ghost_planes[k - n];
            for (Index e = face_begin_[k]; e < face_begin_[k + 1]; ++e) {
              const Face& f = faces[static_cast<std::size_t>(face_list_[e])];
              const FaceShape& shape = shapes.of(face_list_[e]);
              const Vec3 &a = shape.corner[0], &b = shape.corner[1], &c = shape.corner[2];
              const Vec3& nrm = shape.normal;
              const Vec3 sn = to_mat3(stress_[k]) * nrm;  // σ n / ρ²
              if (!nrm.allFinite() || !meets(v_[k], st.v, f, nrm, sn.dot(nrm))) continue;
              const FaceKernel fk = face_kernel(x_[k], shape, hi);
              if (!(fk.phi > 0.0)) continue;
              const Vec3 xc = fk.w[0] * a + fk.w[1] * b + fk.w[2] * c;
              const Vec3 dv =
                  v_[k] - (fk.w[0] * st.v[f[0]] + fk.w[1] * st.v[f[1]] + fk.w[2] * st.v[f[2]]);
              const Vec3 r = x_[k] - xc;
              double pi = 0.0;
              if (dv.dot(r) < 0.0) {
                const double mu = hi * dv.dot(r) / (r.squaredNorm() + 0.01 * hi * hi);
                pi = (-alpha * ci * mu + beta * mu * mu) / rho;
                mu_max = std::max(mu_max, -mu);
              }
              const double scale = mi * rho * fk.phi;
              const Vec3 fk_force = -scale * (2.0 * sn - pi * nrm);
              const Vec3 onto = mirror_direction(fk_force, symmetry_, static_cast<int>(mask));
              force += onto;
              if (mask != 0u) plane_force_[i] += onto - fk_force;
              const Vec3 coef = scale * (sn - pi * nrm);
              heat += coef.dot(dv);
              const Vec3 v_face =
                  fk.w[0] * st.v[f[0]] + fk.w[1] * st.v[f[1]] + fk.w[2] * st.v[f[2]];
              block_terms[blk].push_back(
                  {static_cast<Index>(i), mask, f, fk.w, coef, fk_force, v_face});
            }
          }
          st.f[fp + i] = force;
          heat_rate_[i] = heat;
          const double dt =
              options_.step_factor * pm.h[i] / (ci + 1.2 * (alpha * ci + beta * mu_max));
          if (dt < blocks[blk].dt_stable) blocks[blk] = {dt, static_cast<Index>(i)};
        }
      },
      k_particle_block);
  // The faces' nodes take the opposite of the points' face forces, in particle order; the
  // terms are kept for the heat over the kick (kick_heat).
  face_terms_.clear();
  for (const std::vector<FaceTerm>& terms : block_terms)
    face_terms_.insert(face_terms_.end(), terms.begin(), terms.end());
  term_begin_.assign(n + 1, 0);
  for (const FaceTerm& t : face_terms_) {
    for (int v = 0; v < 3; ++v) st.f[t.face[v]] -= t.w[v] * t.force;
    ++term_begin_[static_cast<std::size_t>(t.particle) + 1];
  }
  for (std::size_t i = 0; i < n; ++i) term_begin_[i + 1] += term_begin_[i];
  StepLimit limit{std::numeric_limits<double>::infinity(), -1};
  for (const StepLimit& b : blocks)
    if (b.dt_stable < limit.dt_stable) limit = b;
  return limit;
}

Index append_matter(ParticleMatter& pm, const Material& m, Index material, double vol0, double h) {
  const double t0 = m.start_temperature();
  pm.h.push_back(h);
  pm.spacing.push_back(std::cbrt(vol0));
  pm.rho.push_back(m.density);
  pm.vol0.push_back(vol0);
  pm.vol.push_back(vol0);
  pm.s.push_back(Sym6{0, 0, 0, 0, 0, 0});
  for (std::vector<double>* a : {&pm.p, &pm.q, &pm.eps_p, &pm.ductile, &pm.ductile_floor,
                                 &pm.w_plastic, &pm.w_viscous, &pm.trace_d})
    a->push_back(0.0);
  pm.sound2.push_back(sound_speed2(m, 0.0, 0.0, eos_terms(m, 0.0), t0));
  pm.temperature.push_back(t0);
  pm.material.push_back(material);
  pm.damage.push_back(Damage::intact);
  pm.plane_impulse.push_back(Vec3::Zero());
  return pm.size() - 1;
}

Index append_cell_matter(ParticleMatter& pm, const State& st, Index tet, double mass, double h,
                         const Material& m, double energy) {
  const double vol = st.vol[tet] > st.vol0[tet]
                         ? particle_volume(m, st.vol[tet], st.vol0[tet], energy)
                         : compressed_volume(m, st.vol[tet], st.vol0[tet], energy, st.p[tet]);
  pm.h.push_back(h);
  pm.spacing.push_back(std::cbrt(st.vol0[tet]));
  pm.rho.push_back(mass / vol);
  pm.vol0.push_back(st.vol0[tet]);
  pm.vol.push_back(vol);
  pm.s.push_back(st.s[tet]);
  pm.p.push_back(st.p[tet]);
  pm.q.push_back(0.0);  // a particle's viscosity acts between pairs
  pm.eps_p.push_back(st.eps_p[tet]);
  pm.ductile.push_back(st.ductile[tet]);
  pm.ductile_floor.push_back(st.ductile_floor[tet]);
  pm.w_plastic.push_back(0.0);  // the cell's works stay booked with the cell
  pm.w_viscous.push_back(0.0);
  pm.sound2.push_back(st.sound2[tet]);
  pm.trace_d.push_back(st.trace_d[tet]);
  pm.temperature.push_back(st.temperature[tet]);
  pm.material.push_back(st.tet_material[tet]);
  pm.damage.push_back(st.damage[tet]);
  pm.plane_impulse.push_back(Vec3::Zero());
  return pm.size() - 1;
}

void Stage::persist(Archive& ar) {
  ar.section("sph");
  ar(neighbours_.begin, neighbours_.list, neighbours_.ghost_source, neighbours_.ghost_planes,
     neighbours_.particles);
  ar(x_, v_, stress_, art_, heat_rate_, plane_force_, face_terms_, term_begin_, ghost_begin_,
     face_begin_, face_list_, fresh_);
}

}  // namespace tc::sph
