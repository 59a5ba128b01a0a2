#include "tetcontact/mesh/generators.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "tetcontact/mesh/surface.hpp"

namespace tc {
namespace {

using Map = std::function<Vec3(const Vec3&)>;  // lattice point in [-1,1]^3 → space

// Blend between the identity (centre) and the radial projection onto the unit ball (surface)
// for the coordinates selected by `dims` (2 for a disk, 3 for a ball):
//   p' = p (1 - b + b r∞/r₂),  b = r∞,
// where r∞ and r₂ are the max- and 2-norms of p. Along a ray p = s·u the mapped radius
// k s + (1 - k) s² (k = r₂/r∞ ≤ √3) grows monotonically, so the map keeps tets positive.
Vec3 blend_to_ball(Vec3 p, int dims) {
  double rinf = 0.0, r2 = 0.0;
  for (int d = 0; d < dims; ++d) {
    rinf = std::max(rinf, std::abs(p[d]));
    r2 += p[d] * p[d];
  }
  r2 = std::sqrt(r2);
  if (r2 == 0.0) return p;
  const double factor = 1.0 - rinf + rinf * rinf / r2;
  for (int d = 0; d < dims; ++d) p[d] *= factor;
  return p;
}

void check_cells(std::array<int, 3> n, const char* what) {
  for (int c : n)
    if (c < 1 || c > 4096)
      throw std::invalid_argument(std::string(what) + ": cell counts must be in [1, 4096]");
}

void push_oriented(TetMesh& m, Tet t) {
  const double v = tet_signed_volume(m.x[t[0]], m.x[t[1]], m.x[t[2]], m.x[t[3]]);
  if (v < 0.0) std::swap(t[2], t[3]);
  m.tets.push_back(t);
}

// The lattice coordinate p ∈ [−1, 1] of an axis of n cells onto the node coordinates `at`
// (n + 1 of them): node i exactly at at[i], a cell's centre (split 12) linearly between.
double on_axis(double p, const std::vector<double>& at) {
  const double n = static_cast<double>(at.size() - 1);
  const double t = 0.5 * (p + 1.0) * n;
  const double i = std::round(t);
  if (std::abs(t - i) < 1e-9) return at[static_cast<std::size_t>(i)];
  const auto i0 = static_cast<std::size_t>(std::clamp(std::floor(t), 0.0, n - 1.0));
  return at[i0] + (t - static_cast<double>(i0)) * (at[i0 + 1] - at[i0]);
}

// Lattice of n[0]×n[1]×n[2] hex cells over [-1,1]^3, mapped by `map`, each hex split.
TetMesh lattice(std::array<int, 3> n, HexSplit split, const Map& map) {
  TetMesh m;
  const int nx = n[0], ny = n[1], nz = n[2];
  auto param = [&](double i, double j, double k) {
    return Vec3(2.0 * i / nx - 1.0, 2.0 * j / ny - 1.0, 2.0 * k / nz - 1.0);
  };
  auto node = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  m.x.reserve(static_cast<std::size_t>(nx + 1) * (ny + 1) * (nz + 1));
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.x.push_back(map(param(i, j, k)));

  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        // Corner of the cell at local offsets (a, b, c) ∈ {0,1}^3.
        auto v = [&](int a, int b, int c) { return node(i + a, j + b, k + c); };
        if (split == HexSplit::six) {
          // Mirror the local frame in each axis whose cell centre lies below the centre plane,
          // so the Kuhn diagonal runs from the corner nearest the centre to the farthest.
          const int fx = (2 * i + 1 < nx), fy = (2 * j + 1 < ny), fz = (2 * k + 1 < nz);
          auto w = [&](std::array<int, 3> o) { return v(o[0] ^ fx, o[1] ^ fy, o[2] ^ fz); };
          static constexpr std::array<std::array<int, 3>, 6> perms = {
              {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
          for (const auto& p : perms) {
            std::array<int, 3> o{0, 0, 0};
            Tet t;
            t[0] = w(o);
            for (int s = 0; s < 3; ++s) {
              o[p[s]] = 1;
              t[s + 1] = w(o);
            }
            push_oriented(m, t);
          }
        } else if (split == HexSplit::five) {
          // Alternate cells are mirrored in x so that face diagonals match.
          const int f = (i + j + k) & 1;
          auto w = [&](int a, int b, int c) { return v(a ^ f, b, c); };
          push_oriented(m, {w(1, 0, 0), w(0, 1, 0), w(0, 0, 1), w(1, 1, 1)});
          push_oriented(m, {w(0, 0, 0), w(1, 0, 0), w(0, 1, 0), w(0, 0, 1)});
          push_oriented(m, {w(1, 1, 0), w(1, 0, 0), w(0, 1, 0), w(1, 1, 1)});
          push_oriented(m, {w(1, 0, 1), w(1, 0, 0), w(0, 0, 1), w(1, 1, 1)});
          push_oriented(m, {w(0, 1, 1), w(0, 1, 0), w(0, 0, 1), w(1, 1, 1)});
        } else {
          const Index centre = static_cast<Index>(m.x.size());
          m.x.push_back(map(param(i + 0.5, j + 0.5, k + 0.5)));
          // The six faces as corner cycles.
          static constexpr std::array<std::array<std::array<int, 3>, 4>, 6> faces = {{
              {{{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}},
              {{{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}},
              {{{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}},
              {{{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}}},
              {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}},
              {{{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}},
          }};
          for (const auto& f : faces) {
            std::array<Index, 4> q;
            for (int c = 0; c < 4; ++c) q[c] = v(f[c][0], f[c][1], f[c][2]);
            // Cut along the diagonal whose corners have even global parity: the rule is the
            // same for both cells sharing the face, so the mesh conforms.
            const auto& c0 = f[0];
            const bool even0 = ((i + c0[0] + j + c0[1] + k + c0[2]) & 1) == 0;
            if (even0) {
              push_oriented(m, {centre, q[0], q[1], q[2]});
              push_oriented(m, {centre, q[0], q[2], q[3]});
            } else {
              push_oriented(m, {centre, q[1], q[2], q[3]});
              push_oriented(m, {centre, q[1], q[3], q[0]});
            }
          }
        }
      }
  return m;
}

}  // namespace

TetMesh make_box(const Vec3& size, std::array<int, 3> cells, HexSplit split) {
  check_cells(cells, "box");
  const Vec3 half = size / 2.0;
  return lattice(cells, split, [&](const Vec3& p) { return Vec3(p.cwiseProduct(half)); });
}

TetMesh make_plate(const Vec3& size, int cells_through_thickness, HexSplit split) {
  if (cells_through_thickness < 1)
    throw std::invalid_argument("plate: cells_through_thickness must be at least 1");
  const double h = size.z() / cells_through_thickness;
  std::array<int, 3> cells{std::max(1, static_cast<int>(std::lround(size.x() / h))),
                           std::max(1, static_cast<int>(std::lround(size.y() / h))),
                           cells_through_thickness};
  return make_box(size, cells, split);
}

std::vector<double> graded_axis(double width, double h, double core, double growth) {
  if (!(width > 0.0 && h > 0.0)) throw std::invalid_argument("plate: sizes must be positive");
  if (!(core > 0.0)) throw std::invalid_argument("plate: core must be positive");
  if (!(growth > 1.0 && growth <= 2.0))
    throw std::invalid_argument("plate: growth must be in (1, 2]");
  const double half = 0.5 * width;
  const long core_cells = std::max(1L, std::lround(0.5 * core / h));
  std::vector<double> right{0.0};  // the nodes from the centre to the rim
  // Less than a cell left outside the core: uniform (a thinner cell at the rim would set the
  // time step).
  if (static_cast<double>(core_cells + 1) * h > half) {
    const long n = std::max(1L, std::lround(half / h));
    for (long i = 1; i <= n; ++i) right.push_back(half * static_cast<double>(i) / n);
  } else {
    for (long i = 1; i <= core_cells; ++i) right.push_back(h * static_cast<double>(i));
    const double rest = half - right.back();
    // m cells of h·growth^k (k = 1..m) span h g (g^m − 1) / (g − 1); the m whose span needs
    // the factor nearest 1 (in ratio) to end on the rim.
    const auto span = [&](long m) {
      return h * growth * (std::pow(growth, static_cast<double>(m)) - 1.0) / (growth - 1.0);
    };
    long m = 1;
    while (span(m) < rest) ++m;
    if (m > 1 && span(m) / rest > rest / span(m - 1)) --m;
    // No graded cell smaller than the core's.
    while (m > 1 && rest / span(m) * growth < 1.0) --m;
    const double f = rest / span(m);
    const double core_end = right.back();
    double size = h * f, x = core_end;
    for (long k = 1; k <= m; ++k) {
      size *= growth;
      x += size;
      right.push_back(k == m ? half : x);
    }
  }
  std::vector<double> at;
  for (auto it = right.rbegin(); it != right.rend(); ++it) at.push_back(-*it);
  at.insert(at.end(), right.begin() + 1, right.end());
  return at;
}

TetMesh make_plate(const Vec3& size, int cells_through_thickness, HexSplit split,
                   const PlateGrading& grading) {
  if (cells_through_thickness < 1)
    throw std::invalid_argument("plate: cells_through_thickness must be at least 1");
  const double h = size.z() / cells_through_thickness;
  const std::vector<double> xs = graded_axis(size.x(), h, grading.core, grading.growth);
  const std::vector<double> ys = graded_axis(size.y(), h, grading.core, grading.growth);
  const std::array<int, 3> cells{static_cast<int>(xs.size() - 1), static_cast<int>(ys.size() - 1),
                                 cells_through_thickness};
  check_cells(cells, "plate");
  const double half_z = 0.5 * size.z();
  return lattice(cells, split, [&](const Vec3& p) {
    return Vec3(on_axis(p.x(), xs), on_axis(p.y(), ys), half_z * p.z());
  });
}

TetMesh make_cylinder(double radius, double height, int cells_across, int cells_axial,
                      HexSplit split) {
  if (split != HexSplit::six)
    throw std::invalid_argument(
        "cylinder: only split 6 is offered; 5 and 12 put slivers in the "
        "wedge-shaped cells at the rim");
  check_cells({cells_across, cells_across, cells_axial}, "cylinder");
  return lattice({cells_across, cells_across, cells_axial}, split, [&](const Vec3& p) {
    Vec3 q = blend_to_ball(p, 2);
    return Vec3(radius * q.x(), radius * q.y(), 0.5 * height * q.z());
  });
}

namespace {

// Stretch of one lattice coordinate p ∈ [−1, 1] with slope `a` at the clustering point:
//   toward 0:   s(p) = p (a + (1 − a)|p|)
//   toward ±1:  the same in the distance from that end, q = (1 ∓ p)/2 → q (a + (1 − a) q).
// Both are monotone (s′ ≥ a > 0) and map [−1, 1] onto itself.
double stretch(double p, double a, int end) {
  if (end == 0) return p * (a + (1.0 - a) * std::abs(p));
  const double q = 0.5 * (1.0 - end * p);
  return end * (1.0 - 2.0 * q * (a + (1.0 - a) * q));
}

}  // namespace

TetMesh make_sphere(double radius, int cells_across, HexSplit split, const Grading& grading) {
  int axis = -1, end = 0;
  if (grading.toward.squaredNorm() > 0.0) {
    for (int d = 0; d < 3; ++d)
      if (std::abs(grading.toward[d]) == 1.0 && grading.toward.squaredNorm() == 1.0) {
        axis = d;
        end = grading.toward[d] > 0 ? 1 : -1;
      }
    if (axis < 0) throw std::invalid_argument("sphere: refine_toward must be ±x, ±y or ±z");
    if (!(grading.factor > 0.0 && grading.factor <= 1.0))
      throw std::invalid_argument("sphere: refine_factor must be in (0, 1]");
  }
  // The clustering fades away from the pole, so that cells far from it keep their shape:
  // along the axis with the lateral distance from it, across it with the distance from the
  // pole's face. Each coordinate still maps [−1, 1] onto itself.
  const auto graded = [&](const Vec3& p) {
    if (axis < 0) return p;
    const double a = grading.factor;
    const int l1 = (axis + 1) % 3, l2 = (axis + 2) % 3;
    const double lateral = std::max(std::abs(p[l1]), std::abs(p[l2]));  // 0 on the axis
    const double along = 0.5 * (1.0 - end * p[axis]);                   // 0 at the pole's face
    Vec3 q;
    q[axis] = stretch(p[axis], a + (1.0 - a) * lateral, end);
    q[l1] = stretch(p[l1], a + (1.0 - a) * along, 0);
    q[l2] = stretch(p[l2], a + (1.0 - a) * along, 0);
    return q;
  };
  if (split != HexSplit::six)
    throw std::invalid_argument(
        "sphere: only split 6 is offered; 5 and 12 put slivers in the "
        "wedge-shaped cells under the surface");
  check_cells({cells_across, cells_across, cells_across}, "sphere");
  return lattice({cells_across, cells_across, cells_across}, split,
                 [&](const Vec3& p) { return Vec3(radius * blend_to_ball(graded(p), 3)); });
}

void translate(TetMesh& mesh, const Vec3& offset) {
  for (Vec3& p : mesh.x) p += offset;
}

void rotate(TetMesh& mesh, const Vec3& axis, double radians) {
  const Mat3 r = Eigen::AngleAxisd(radians, axis.normalized()).toRotationMatrix();
  for (Vec3& p : mesh.x) p = r * p;
}

void scale(TetMesh& mesh, double factor) {
  for (Vec3& p : mesh.x) p *= factor;
}

double min_dihedral_angle_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const std::array<Vec3, 4> p{a, b, c, d};
  std::array<Vec3, 4> n;  // outward face normals, face i opposite node i
  for (int i = 0; i < 4; ++i) {
    const auto& f = k_tet_faces[i];
    n[i] = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).normalized();
  }
  double worst = 180.0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      // Interior dihedral angle along the edge shared by faces i and j.
      const double cosang = std::clamp(-n[i].dot(n[j]), -1.0, 1.0);
      worst = std::min(worst, std::acos(cosang) * 180.0 / M_PI);
    }
  return worst;
}

}  // namespace tc
