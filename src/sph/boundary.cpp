#include "tetcontact/sph/boundary.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <numbers>

#include "tetcontact/sph/kernel.hpp"

namespace tc::sph {

namespace {

// The kernel's radial integral in the plane's polar coordinates: with s the distance from the
// particle, F0(s) = ∫_0^s W(r) r dr = F(s/h) / (π h), F(q) = ∫_0^q w(u) u du for the spline's
// shape w (kernel.hpp):
//
//   F(q) = q²/2 − 3/8 q⁴ + 3/20 q⁵                         0 ≤ q < 1
//        = 7/20 − 1/8 (2 − q)⁴ + 1/20 (2 − q)⁵             1 ≤ q < 2
//        = 7/20                                            q ≥ 2
//
// Both pieces are computed and one chosen (a select, which the lanes below run as a blend): the
// chosen piece's doubles are those of the branches it stands for.
[[gnu::always_inline]] inline double radial(double q) {
  const double q2 = q * q;
  const double inner = q2 * (0.5 - 0.375 * q2 + 0.15 * q2 * q);
  const double v = 2.0 - q, v4 = v * v * v * v;
  const double outer = 0.35 - 0.125 * v4 + 0.05 * v4 * v;
  return q < 1.0 ? inner : (q < 2.0 ? outer : 0.35);
}

// Gauss–Legendre, six points on [−1, 1].
constexpr std::array<double, 6> k_gauss_x{-0.932469514203152, -0.661209386466265,
                                          -0.238619186083197, 0.238619186083197,
                                          0.661209386466265,  0.932469514203152};
constexpr std::array<double, 6> k_gauss_w{0.171324492379170, 0.360761573048139, 0.467913934572691,
                                          0.467913934572691, 0.360761573048139, 0.171324492379170};

// The edges' Gauss points of one particle and face: at most three edges, three pieces an edge
// (between the kernel's knees), six points a piece. Each point's position t along its edge, its
// edge's p_e and its weight (half the piece times the rule's weight) in; the integrands
// (F(s) − F(d)) / ρ² and F(s) out.
struct GaussPoints {
  static constexpr int k_max = 3 * 3 * 6;
  int count = 0;
  alignas(64) double t[k_max];
  alignas(64) double pe[k_max];
  alignas(64) double weight[k_max];
  alignas(64) double ratio[k_max];
  alignas(64) double f[k_max];
};

// The integrands at every point, one point a lane: s = √(ρ² + d²), ρ² = t² + p_e²; where ρ → 0
// (the foot on the edge) the ratio's limit w(d/h) / (2 h²) in F's units, `at_foot`. No step
// depends on another point, so the loop runs in the widest lanes its copy is compiled for; no
// product and sum are fused (boundary.cpp is compiled with -ffp-contract=off), so every copy
// gives the one-point-at-a-time doubles.
[[gnu::always_inline]] inline void integrands(GaussPoints& g, double d2, double inv_h, double f_d,
                                              double near2, double at_foot) {
  const int count = g.count;
  for (int i = 0; i < count; ++i) {
    const double rho2 = g.t[i] * g.t[i] + g.pe[i] * g.pe[i];
    const double f = radial(std::sqrt(rho2 + d2) * inv_h);
    g.f[i] = f;
    g.ratio[i] = rho2 > near2 ? (f - f_d) / rho2 : at_foot;
  }
}

using Integrands = void (*)(GaussPoints&, double, double, double, double, double);

// One point at a time: the reference.
__attribute__((optimize("no-tree-vectorize"))) void scalar_integrands(GaussPoints& g, double d2,
                                                                      double inv_h, double f_d,
                                                                      double near2,
                                                                      double at_foot) {
  integrands(g, d2, inv_h, f_d, near2, at_foot);
}

#define TC_LANE_COPY(NAME, TARGET)                                                    \
  TARGET void NAME(GaussPoints& g, double d2, double inv_h, double f_d, double near2, \
                   double at_foot) {                                                  \
    integrands(g, d2, inv_h, f_d, near2, at_foot);                                    \
  }
TC_LANE_COPY(sse2_integrands, )
TC_LANE_COPY(avx2_integrands, TC_TARGET_AVX2)
TC_LANE_COPY(avx512_integrands, TC_TARGET_AVX512)
#undef TC_LANE_COPY

Integrands copy_of(Lanes lanes) {
  return copy_for<Integrands>(lanes, &scalar_integrands, &sse2_integrands, &avx2_integrands,
                              &avx512_integrands);
}

std::atomic<Lanes> face_lanes{widest_lanes()};
std::atomic<Integrands> integrands_copy{copy_of(widest_lanes())};

}  // namespace

Lanes set_face_lanes(Lanes lanes) {
  integrands_copy.store(copy_of(runnable_lanes(lanes, "face")));
  return face_lanes.exchange(lanes);
}

// The triangle cut into n² sub-triangles of area A/n² by the lines λ_a = i/n, λ_b = j/n: the
// "upright" ones have their centroids at barycentric ((i + 1/3)/n, (j + 1/3)/n) for i + j < n,
// the inverted ones at ((i + 2/3)/n, (j + 2/3)/n) for i + j < n − 1.
FaceKernel face_kernel(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, double h,
                       int n) {
  FaceKernel out;
  const double area = 0.5 * (b - a).cross(c - a).norm();
  if (!(area > 0.0) || n < 1) return out;
  const double cell = area / (n * n), inv = 1.0 / n;
  std::array<double, 3> sum{0.0, 0.0, 0.0};
  const auto add = [&](double la, double lb) {
    const double lc = 1.0 - la - lb;
    const double wk = kernel((la * a + lb * b + lc * c - x).norm(), h);
    sum[0] += wk * la;
    sum[1] += wk * lb;
    sum[2] += wk * lc;
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      add((i + 1.0 / 3.0) * inv, (j + 1.0 / 3.0) * inv);
      if (i + j < n - 1) add((i + 2.0 / 3.0) * inv, (j + 2.0 / 3.0) * inv);
    }
  const double phi = cell * (sum[0] + sum[1] + sum[2]);
  if (!(phi > 0.0)) return out;
  out.phi = phi;
  for (int v = 0; v < 3; ++v) out.w[v] = cell * sum[v] / phi;
  return out;
}

// What of the face does not depend on the particle.
FaceShape face_shape(const Vec3& a, const Vec3& b, const Vec3& c) {
  FaceShape f;
  f.corner = {a, b, c};
  f.lo = a.cwiseMin(b).cwiseMin(c);
  f.hi = a.cwiseMax(b).cwiseMax(c);
  f.normal = (b - a).cross(c - a);
  f.twice_area = f.normal.norm();
  f.normal /= f.twice_area;
  for (int e = 0; e < 3; ++e) {
    Vec3 dir = f.corner[(e + 1) % 3] - f.corner[e];
    f.length[e] = dir.norm();
    dir /= f.length[e];
    f.dir[e] = dir;
    f.nu[e] = dir.cross(f.normal);
  }
  for (int v = 0; v < 3; ++v) {
    const Vec3& q0 = f.corner[(v + 1) % 3];
    const Vec3& q1 = f.corner[(v + 2) % 3];
    f.grad[v] = f.normal.cross(q1 - q0) / f.twice_area;
  }
  return f;
}

FaceKernel face_kernel(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, double h) {
  return face_kernel(x, face_shape(a, b, c), h);
}

// On the face's plane, with p the particle's foot, d its distance, ρ = |y − p| and s² = ρ² + d²:
// W = ∇·((y − p) (F0(s) − F0(d)) / ρ²) and (y − p) W = ∇(F0(s) − F0(2h)), so by the divergence
// theorem in the plane each is a sum over the triangle's edges e (outward normal ν_e, the foot
// at signed distance p_e = (y − p)·ν_e from its line, t the position along it):
//
//   Φ = Σ_e p_e ∫_e (F0(s) − F0(d)) / (t² + p_e²) dt,
//   ∫ (y − p) W dS = Σ_e ν_e ∫_e (F0(s) − F0(2h)) dt.
//
// Beyond the kernel's reach F0(s) = F0(2h): there the first is (F0(2h) − F0(d)) times the angle
// the piece of edge subtends at the foot, in closed form, and the second nothing; within reach
// the integrands are smooth between the points where s = h and s = 2h but for a fifth-power
// point where the particle lies on the edge's line, and six Gauss points per piece integrate
// them to about 1e-5 (a foot on an edge's line is no singularity: the integrand is bounded and
// p_e = 0). The weights follow from the first moment, the barycentric coordinates being
// affine: ∫ W λ_v dS = λ_v(p) Φ + ∇λ_v · ∫ (y − p) W dS.
FaceKernel face_kernel(const Vec3& x, const FaceShape& face, double h) {
  FaceKernel out;
  const double reach = k_support * h;
  // A face whose box lies beyond reach: nothing (what the edges' sums give, without them).
  const Vec3 gap = (face.lo - x).cwiseMax(x - face.hi);
  if (gap.cwiseMax(0.0).squaredNorm() >= reach * reach) return out;
  const double twice_area = face.twice_area;
  if (!(twice_area > 0.0) || !(h > 0.0)) return out;
  const Vec3& nrm = face.normal;
  const std::array<Vec3, 3>& corner = face.corner;
  const double d = (x - corner[0]).dot(nrm);
  if (!(std::abs(d) < reach)) return out;
  const Vec3 p = x - d * nrm;
  const double d2 = d * d, h2 = h * h, inv_h = 1.0 / h;
  const double f_d = radial(std::abs(d) * inv_h), f_reach = radial(k_support);
  // Each edge in the plane: its outward normal ν, the foot's distance p_e from its line, its
  // ends t0, t1 along it; the line within reach where |t| < t_reach.
  struct Edge {
    Vec3 nu;
    double pe, t0, t1, c2, t_reach;
  };
  std::array<Edge, 3> edges;
  bool inside = true, in_reach = false;  // the foot within the triangle; an edge within reach
  for (int e = 0; e < 3; ++e) {
    Edge& g = edges[e];
    const Vec3& s0 = corner[e];
    g.nu = face.nu[e];
    g.pe = (s0 - p).dot(g.nu);
    g.t0 = (s0 - p).dot(face.dir[e]);
    g.t1 = g.t0 + face.length[e];
    g.c2 = g.pe * g.pe + d2;
    g.t_reach = g.c2 < 4.0 * h2 ? std::sqrt(4.0 * h2 - g.c2) : 0.0;
    inside = inside && g.pe >= 0.0;
    in_reach = in_reach || (g.t_reach > 0.0 && g.t1 > -g.t_reach && g.t0 < g.t_reach);
  }
  // Wholly out of reach: nothing (not the angles' round-off).
  if (!inside && !in_reach) return out;
  // The pieces within reach, and their Gauss points, edge by edge.
  GaussPoints points;
  std::array<int, 4> first{0, 0, 0, 0};  // edge e's points: [first[e], first[e + 1])
  for (int e = 0; e < 3; ++e) {
    const Edge& g = edges[e];
    first[e] = points.count;
    const double t0 = g.t0, t1 = g.t1, c2 = g.c2, t_reach = g.t_reach;
    if (!(t_reach > 0.0) || t1 <= -t_reach || t0 >= t_reach) continue;
    // The kernel's knee at |t| = t_knee.
    const double t_knee = c2 < h2 ? std::sqrt(h2 - c2) : 0.0;
    const std::array<double, 4> cuts{-t_reach, -t_knee, t_knee, t_reach};
    for (int k = 0; k < 3; ++k) {
      const double ta = std::max(t0, cuts[k]), tb = std::min(t1, cuts[k + 1]);
      if (!(tb > ta)) continue;
      const double mid = 0.5 * (ta + tb), half = 0.5 * (tb - ta);
      for (int q = 0; q < 6; ++q) {
        const int at = points.count++;
        points.t[at] = mid + half * k_gauss_x[q];
        points.pe[at] = g.pe;
        points.weight[at] = half * k_gauss_w[q];
      }
    }
  }
  first[3] = points.count;
  // (F(s) − F(d)) / ρ² → w(d/h) / (2 h²) as ρ → 0.
  const double at_foot = 0.5 * kernel(std::abs(d), h) * std::numbers::pi * h;
  if (points.count > 0)
    integrands_copy.load(std::memory_order_relaxed)(points, d2, inv_h, f_d, 1e-24 * h2, at_foot);
  double phi = 0.0;
  Vec3 moment = Vec3::Zero();
  for (int e = 0; e < 3; ++e) {
    const Edge& g = edges[e];
    const double pe = g.pe, t0 = g.t0, t1 = g.t1, t_reach = g.t_reach;
    // The angle [ta, tb] subtends at the foot, signed as p_e.
    const auto angle = [&](double ta, double tb) {
      return tb > ta ? std::atan2(pe * (tb - ta), pe * pe + ta * tb) : 0.0;
    };
    phi += (f_reach - f_d) * (angle(t0, std::min(t1, -t_reach)) + angle(std::max(t0, t_reach), t1));
    if (!(t_reach > 0.0) || t1 <= -t_reach || t0 >= t_reach) continue;
    double along_phi = 0.0, along_moment = 0.0;
    for (int i = first[e]; i < first[e + 1]; ++i) {
      along_phi += points.weight[i] * points.ratio[i];
      along_moment += points.weight[i] * (points.f[i] - f_reach);
    }
    phi += pe * along_phi;
    moment += along_moment * g.nu;
  }
  // F0 = F / (π h): back to the kernel's units.
  const double scale = inv_h / std::numbers::pi;
  phi *= scale;
  moment *= scale;
  if (!(phi > 0.0)) return out;
  out.phi = phi;
  for (int v = 0; v < 3; ++v) {
    const Vec3& q0 = corner[(v + 1) % 3];
    const Vec3& q1 = corner[(v + 2) % 3];
    const double at_foot = (q1 - q0).cross(p - q0).dot(nrm) / twice_area;
    out.w[v] = std::clamp(at_foot + face.grad[v].dot(moment) / phi, 0.0, 1.0);
  }
  // The weights lie in [0, 1] (W ≥ 0 and λ_v ∈ [0, 1] on the face); on a needle of a face the
  // barycentric gradient is large and the edges' sums cancel, so they are held there and
  // summed to 1.
  const double sum = out.w[0] + out.w[1] + out.w[2];
  for (double& wv : out.w) wv /= sum;
  return out;
}

}  // namespace tc::sph
