// CGAL's exact predicates for the penetration diagnostics. The only file that includes CGAL.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "tetcontact/diagnostics/penetration.hpp"

namespace tc {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
K::Point_3 pt(const Vec3& v) {
  return K::Point_3(v.x(), v.y(), v.z());
}

}  // namespace

bool exact_point_in_tet(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const K::Tetrahedron_3 tet(pt(a), pt(b), pt(c), pt(d));
  if (tet.is_degenerate()) return false;
  return tet.bounded_side(pt(p)) != CGAL::ON_UNBOUNDED_SIDE;
}

bool exact_point_strictly_in_tet(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                 const Vec3& d) {
  const K::Tetrahedron_3 tet(pt(a), pt(b), pt(c), pt(d));
  if (tet.is_degenerate()) return false;
  return tet.bounded_side(pt(p)) == CGAL::ON_BOUNDED_SIDE;
}

bool exact_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const K::Triangle_3 tri(pt(a), pt(b), pt(c));
  if (tri.is_degenerate()) return false;
  return tri.has_on(pt(p));
}

bool exact_segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                                    const Vec3& c) {
  const K::Point_3 P = pt(p), Q = pt(q), A = pt(a), B = pt(b), C = pt(c);
  if (CGAL::collinear(A, B, C)) return false;
  const auto sp = CGAL::orientation(A, B, C, P);
  const auto sq = CGAL::orientation(A, B, C, Q);
  if (sp == CGAL::COPLANAR || sq == CGAL::COPLANAR || sp == sq) return false;
  // The line PQ passes strictly inside the triangle: the same non-zero orientation against
  // each of its edges (on an edge or a vertex the segment only touches it).
  const auto e1 = CGAL::orientation(P, Q, A, B);
  const auto e2 = CGAL::orientation(P, Q, B, C);
  const auto e3 = CGAL::orientation(P, Q, C, A);
  return e1 != CGAL::COPLANAR && e1 == e2 && e2 == e3;
}

}  // namespace tc
