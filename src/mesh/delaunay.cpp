#include "tetcontact/mesh/delaunay.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/make_mesh_3.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace tc {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Domain = CGAL::Labeled_mesh_domain_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;

// The unit ball, negative inside (the domain is meshed at unit radius and scaled).
K::FT unit_ball(const Point& p) {
  return p.x() * p.x() + p.y() * p.y() + p.z() * p.z() - 1.0;
}

// h(x) = min(cell, refine + growth |x − pole|), in units of the radius.
struct SizeField {
  using FT = K::FT;
  double cell, refine, growth;
  Vec3 pole;
  bool graded;
  double at(double d) const { return graded ? std::min(cell, refine + growth * d) : cell; }
  FT operator()(const Point& p, int, const Domain::Index&) const {
    return at((Vec3(p.x(), p.y(), p.z()) - pole).norm());
  }
};

// Cells the size field asks for, roughly: the sphere of radius d about a surface point has
// 2π d² (1 − d/2) of its area inside the unit ball, and a cell of circumradius bound h takes
// about 0.12 h³ (measured over four Hertz meshes: 0.09 to 0.17).
double estimated_cells(const SizeField& f) {
  constexpr int n = 4000;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double d = (i + 0.5) * 2.0 / n, h = f.at(d);
    sum += 2.0 * M_PI * d * d * (1.0 - 0.5 * d) / (0.12 * h * h * h) * (2.0 / n);
  }
  return sum;
}

}  // namespace

TetMesh mesh_ball(double radius, const BallSizing& s) {
  const auto fail = [](const std::string& what) {
    throw std::invalid_argument("sphere (cell_size): " + what);
  };
  const bool graded = s.refine_toward.squaredNorm() > 0.0;
  if (!(radius > 0.0 && std::isfinite(radius))) fail("radius must be positive");
  if (!(s.cell_size > 0.0 && s.cell_size <= radius)) fail("cell_size must be in (0, radius]");
  if (graded) {
    if (!std::isfinite(s.refine_toward.squaredNorm())) fail("refine_toward must be finite");
    if (!(s.refine_size > 0.0 && s.refine_size <= s.cell_size))
      fail("refine_size must be in (0, cell_size]");
    if (!(radius / s.refine_size <= 1e4)) fail("refine_size must be at least radius / 10^4");
    if (!(s.growth > 0.0 && s.growth <= 1.0)) fail("growth must be in (0, 1]");
  }
  const SizeField field{s.cell_size / radius, s.refine_size / radius, s.growth,
                        graded ? Vec3(s.refine_toward.normalized()) : Vec3::Zero(), graded};
  const double estimate = estimated_cells(field);
  if (estimate > 5e6)
    fail("these sizes ask for about " + std::to_string(static_cast<long>(estimate)) +
         " tets (more than 5 million): raise cell_size, refine_size or growth");

  namespace p = CGAL::parameters;
  const Domain domain = Domain::create_implicit_mesh_domain(
      unit_ball, K::Sphere_3(CGAL::ORIGIN, 4.0), p::relative_error_bound = 1e-12);
  // Surface triangles and cells both follow the size field; the facet distance keeps the
  // faceted surface within a fifth of the smallest size of the sphere.
  const Criteria criteria(p::facet_angle = 25.0, p::facet_size = field,
                          p::facet_distance = 0.2 * (graded ? field.refine : field.cell),
                          p::cell_radius_edge_ratio = 2.0, p::cell_size = field);
  const C3t3 c3t3 =
      CGAL::make_mesh_3<C3t3>(domain, criteria, p::no_lloyd(), p::no_odt(), p::no_perturb(),
                              p::exude(p::time_limit = 0, p::sliver_bound = 15));

  // Nodes numbered in the order the cells list them (the same every run).
  TetMesh mesh;
  std::map<Tr::Vertex_handle, Index> index;
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    Tet t;
    for (int k = 0; k < 4; ++k) {
      const Tr::Vertex_handle v = c->vertex(k);
      auto [it, added] = index.emplace(v, static_cast<Index>(mesh.x.size()));
      if (added) {
        const Point& q = v->point().point();
        Vec3 x(q.x(), q.y(), q.z());
        // Surface nodes onto the sphere itself (the oracle leaves them 1e-12 off).
        if (c3t3.in_dimension(v) < 3) x.normalize();
        mesh.x.push_back(radius * x);
      }
      t[k] = it->second;
    }
    if (tet_signed_volume(mesh.x[t[0]], mesh.x[t[1]], mesh.x[t[2]], mesh.x[t[3]]) < 0.0)
      std::swap(t[2], t[3]);
    mesh.tets.push_back(t);
  }
  if (mesh.tets.empty()) fail("the mesher returned no cells");
  return mesh;
}

}  // namespace tc
