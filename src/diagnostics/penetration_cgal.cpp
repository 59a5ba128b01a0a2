// CGAL's exact predicates for the penetration diagnostics. The only file that includes CGAL.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

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

bool exact_segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                                    const Vec3& c) {
  const K::Triangle_3 tri(pt(a), pt(b), pt(c));
  if (tri.is_degenerate()) return false;
  const auto sp = CGAL::orientation(pt(a), pt(b), pt(c), pt(p));
  const auto sq = CGAL::orientation(pt(a), pt(b), pt(c), pt(q));
  if (sp == CGAL::COPLANAR || sq == CGAL::COPLANAR || sp == sq) return false;  // touches only
  return CGAL::do_intersect(K::Segment_3(pt(p), pt(q)), tri);
}

}  // namespace tc
