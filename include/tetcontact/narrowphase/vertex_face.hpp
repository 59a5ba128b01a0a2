// Vertex–face primitives: point in tetrahedron, closest point on a triangle, and the swept
// vertex–face test over a step.
#pragma once

#include <array>
#include <optional>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

/// The contact-boundary notes §3: p lies inside (or on) the positively oriented tet (a, b, c, d)
/// iff n_i · (p − x_i) ≤ 0 for the outward normal n_i of every face and a point x_i of it.
bool point_in_tet(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// The rim tolerance of node–face contact, as a fraction of a face's longest edge: a point up
/// to this far outside a face (measured from the face) still counts as over it. behind_face
/// accepts with it and the contact's layer boxes are widened by it; binding lists on and off
/// give identical contacts only while the two agree, so both use this one constant.
inline constexpr double k_rim_tolerance = 1e-3;

/// Whether p lies behind the plane of the outward triangle (a, b, c) (normal (b−a)×(c−a)) by
/// at most `depth`, and projects into the triangle or within k_rim_tolerance of its longest
/// edge of it
/// (a node on the rim of one surface stays on the rim of the other under round-off): the
/// node–face contact condition of the contact-boundary notes, a node that has entered the other
/// body's boundary layer. Everything it accepts lies in the prism's box widened by k_rim_tolerance
/// of the longest edge.
bool behind_face(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double depth);

/// Closest point of triangle (a, b, c) to p: barycentric weights (≥ 0, sum 1) and distance.
struct TrianglePoint {
  std::array<double, 3> w{1.0, 0.0, 0.0};
  double distance = 0.0;
};
TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Closest points of segments [a0, a1] and [b0, b1]: parameters α, β ∈ [0, 1] and the points
/// (Dobritsa et al.'s d = (1−α) x_a + α x_b on the first, c = (1−β) x_e + β x_f on the second).
struct SegmentPoints {
  double alpha = 0.0, beta = 0.0;
  Vec3 on_a = Vec3::Zero(), on_b = Vec3::Zero();
};
SegmentPoints closest_points_on_segments(const Vec3& a0, const Vec3& a1, const Vec3& b0,
                                         const Vec3& b1);

}  // namespace tc
