// Certified floating-point CCD: decides the non-degenerate majority of queries in interval
// arithmetic, and says "unknown" for the rest, which the exact path answers.
//
// The coplanarity determinant (Dobritsa et al. eq. 13) and the inside test's orientation
// polynomials are formed once as polynomials in t in doubles, each coefficient with a bound on
// its error carried through every operation (midpoint and radius), and enclosed as intervals,
// unless a separating axis over the whole step, in doubles with a certified
// error bound, already tells the primitives apart (most pairs of a contact interface, sliding
// past each other). The step [0, 1] is cut into time intervals T, on which each polynomial is
// enclosed by its centred form (Taylor coefficients at T's middle), so that
//   - T is dropped when the determinant is nonzero on all of T, or the inside test fails at
//     every time of T (by its orientations, or, where those are too close to 0 to sign, as for
//     nearly parallel coplanar edges, by a separating axis: the primitives' projections on a
//     direction, enclosed over T, are disjoint);
//   - a collision is certain when the determinant has opposite strict signs at T's ends (a root
//     inside, by continuity) and the inside test holds strictly at every time of T;
//   - otherwise T is split in two (off-centre, 15/32 : 17/32, so that roots at 1/2, 1/4, …
//     do not sit on a split point), up to a fixed depth and a fixed number of intervals.
// Touching (a barycentric coordinate exactly 0), roots at interval ends, double roots and
// motions coplanar all step come out "unknown"; a query that may be coplanar and meeting at
// t = 0 or 1 (resting contact) does so at once.
#pragma once

#include <array>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

enum class Certain { no, yes, unknown };

/// Same point order as exact_vertex_face_ccd / exact_edge_edge_ccd.
Certain interval_vertex_face_ccd(const std::array<Vec3, 8>& q);
Certain interval_edge_edge_ccd(const std::array<Vec3, 8>& q);

}  // namespace tc
