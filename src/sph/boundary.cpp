#include "tetcontact/sph/boundary.hpp"

#include <algorithm>
#include <cmath>

#include "tetcontact/sph/kernel.hpp"

namespace tc::sph {

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

// Adaptive: the triangle halved along its edges (four alike) until its longest edge is at most
// h, the parts beyond the kernel's reach dropped, each part by Dunavant's six-point rule of
// degree 4 (D. A. Dunavant, Int. J. Numer. Methods Eng. 21, 1129, 1985).
FaceKernel face_kernel(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, double h) {
  static constexpr double k_a = 0.445948490915965, k_b = 1.0 - 2.0 * k_a, k_wa = 0.223381589678011;
  static constexpr double k_c = 0.091576213509771, k_d = 1.0 - 2.0 * k_c, k_wc = 0.109951743655322;
  static constexpr double k_rule[6][4] = {{k_a, k_a, k_b, k_wa}, {k_a, k_b, k_a, k_wa},
                                          {k_b, k_a, k_a, k_wa}, {k_c, k_c, k_d, k_wc},
                                          {k_c, k_d, k_c, k_wc}, {k_d, k_c, k_c, k_wc}};
  FaceKernel out;
  const double reach = k_support * h;
  constexpr double k_part = 1.0;  // the parts' longest edge, over h
  // A part: its corners in the face's barycentric coordinates.
  struct Part {
    std::array<Vec3, 3> l;
  };
  const auto point = [&](const Vec3& l) { return Vec3(l[0] * a + l[1] * b + l[2] * c); };
  std::array<double, 3> sum{0.0, 0.0, 0.0};
  if (!((b - a).cross(c - a).squaredNorm() > 0.0)) return out;
  // Depth first: at most 3 parts wait per level of halving (a stack of 64 holds 21 levels).
  std::array<Part, 64> stack;
  std::size_t top = 0;
  stack[top++] = {{Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}};
  while (top > 0) {
    const Part part = stack[--top];
    const Vec3 p0 = point(part.l[0]), p1 = point(part.l[1]), p2 = point(part.l[2]);
    const Vec3 mid = (p0 + p1 + p2) / 3.0;
    const double radius = std::sqrt(
        std::max({(p0 - mid).squaredNorm(), (p1 - mid).squaredNorm(), (p2 - mid).squaredNorm()}));
    if ((mid - x).norm() - radius >= reach) continue;  // wholly out of reach
    const double longest = std::max({(p1 - p0).norm(), (p2 - p1).norm(), (p0 - p2).norm()});
    if (longest > k_part * h && top + 4 <= stack.size()) {
      const Vec3 m01 = 0.5 * (part.l[0] + part.l[1]), m12 = 0.5 * (part.l[1] + part.l[2]),
                 m20 = 0.5 * (part.l[2] + part.l[0]);
      stack[top++] = {{part.l[0], m01, m20}};
      stack[top++] = {{m01, part.l[1], m12}};
      stack[top++] = {{m20, m12, part.l[2]}};
      stack[top++] = {{m01, m12, m20}};
      continue;
    }
    const double area = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    for (const auto& q : k_rule) {
      const Vec3 l = q[0] * part.l[0] + q[1] * part.l[1] + q[2] * part.l[2];
      const double wk = q[3] * area * kernel((point(l) - x).norm(), h);
      for (int v = 0; v < 3; ++v) sum[v] += wk * l[v];
    }
  }
  const double phi = sum[0] + sum[1] + sum[2];
  if (!(phi > 0.0)) return out;
  out.phi = phi;
  for (int v = 0; v < 3; ++v) out.w[v] = sum[v] / phi;
  return out;
}

}  // namespace tc::sph
