// Certified floating-point CCD: decides the non-degenerate majority of queries in interval
// arithmetic, and says "unknown" for the rest, which the exact path answers.
//
// Unless a separating axis over the whole step, in doubles with a certified error bound,
// already tells the primitives apart (most pairs of a contact interface, sliding past each
// other), the coplanarity determinant f (Dobritsa et al. eq. 13) is formed as a cubic in t from
// its certified Bernstein sums (coplanarity.hpp), each coefficient enclosed as an interval. The
// step [0, 1] is cut into time spans T, on which a polynomial is enclosed by its centred form
// (Taylor coefficients at T's middle), so that
//   - T is dropped when f is nonzero on all of T;
//   - where f is monotone on T (f' of one strict sign) with strict signs at T's ends, it has no
//     root (the signs agree) or one, which is bracketed by times [a, b] where f's signs are
//     certified opposite (Newton's guess in doubles, then false position), a few 2⁻⁴⁵ wide; the
//     inside test is asked on [a, b] alone, on the points' positions over [a, b] as values
//     with error bounds: no there is no in T, yes there is a collision (f changes sign inside
//     [a, b]); undecided on a bracket as narrow as f's certified signs allow, once more on the
//     polynomials and then "unknown" (touching or nearly so at the root);
//   - otherwise T is dropped when the inside test fails at every time of T, on the inside
//     test's orientation polynomials (formed in doubles with error bounds, bounded_poly.hpp, at
//     the first such span) or, where those are too close to 0 to sign, as for nearly parallel
//     coplanar edges, by a separating axis over T; a collision is certain when f has opposite
//     strict signs at T's ends and the inside test holds strictly at every time of T; else T is
//     split in two (off-centre, 15/32 : 17/32, so that roots at 1/2, 1/4, … do not sit on a
//     split point), up to a fixed depth and a fixed number of spans.
// Touching (a barycentric coordinate exactly 0), roots at span ends, double roots and motions
// coplanar all step come out "unknown"; a query that may be coplanar and meeting at t = 0 or 1
// (resting contact) does so at once.
#pragma once

#include <array>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

enum class Certain { no, yes, unknown };

/// Same point order as exact_vertex_face_ccd / exact_edge_edge_ccd.
Certain interval_vertex_face_ccd(const std::array<Vec3, 8>& q);
Certain interval_edge_edge_ccd(const std::array<Vec3, 8>& q);

}  // namespace tc
