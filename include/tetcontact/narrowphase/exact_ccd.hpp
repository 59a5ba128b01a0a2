// Exact continuous collision queries: every point moves linearly from its position at t = 0
// to its position at t = 1, and the answer is the exact mathematical one (touching counts; a
// motion that stays coplanar the whole step is handled; parallel, collinear, zero-length and
// degenerate primitives are handled).
//
// Method (exact integer arithmetic: the coordinates times one power of two are integers, and
// every time where a sign is asked is a dyadic rational):
//   - the coplanarity condition det[…](t) = 0 is a polynomial of degree ≤ 3 (Dobritsa et al. eq.
//   13);
//     its real roots in [0, 1] are isolated with Sturm sequences on its square-free part;
//   - at each root the intersection test needs only the signs of a few polynomials of the
//     coordinates; a sign at an algebraic root is 0 exactly when the polynomial shares that
//     root (gcd), otherwise the isolating interval is refined until the sign is constant;
//   - when the condition is identically zero (coplanar all step), the primitives meet at some
//     time iff they meet at t = 0, at t = 1, or when a vertex passes over an edge of the other
//     (in a plane, a proper crossing and a vertex strictly inside a triangle persist under
//     small motions), and each vertex–edge passage is the same kind of question of degree 2.
#pragma once

#include <array>
#include <optional>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

/// Vertex–face: q = v(0), f0(0), f1(0), f2(0), v(1), f0(1), f1(1), f2(1).
bool exact_vertex_face_ccd(const std::array<Vec3, 8>& q);

/// Edge–edge: q = a0(0), a1(0), b0(0), b1(0), a0(1), a1(1), b0(1), b1(1).
bool exact_edge_edge_ccd(const std::array<Vec3, 8>& q);

/// The filters that run before the exact integer path, in this order: the exact test of the
/// primitives' boxes over the step, the certified Bernstein test of the coplanarity
/// determinant, the certified interval subdivision (interval_ccd.hpp). Each answers only where
/// it is certain, so the answer never depends on them; with all three off the integer path
/// answers alone: the oracle each filter is tested against.
struct CcdFilters {
  bool boxes = true;
  bool coplanarity = true;
  bool interval = true;
};
bool exact_vertex_face_ccd(const std::array<Vec3, 8>& q, const CcdFilters& filters);
bool exact_edge_edge_ccd(const std::array<Vec3, 8>& q, const CcdFilters& filters);

/// The exact path's shortcuts: its constructions (moving points, cross and dot products, the
/// static predicates) on fixed-width integers of 4, 6 or 8 words when the query's exponents
/// spread over at most 6, 38 or 70 binary orders (GMP integers beyond), and each sign at a root
/// certified in doubles before the exact test. Off: GMP integers throughout and every sign by
/// the exact test alone (the reference the tests hold the shortcuts to). On by default.
void set_exact_ccd_shortcuts(bool on);

/// An observer of the yes/no queries above (the two-argument-free entry points, which contact
/// detection and the step's verification call), for `profile --ccd-queries`: called with each
/// query, from any thread, before it is answered. nullptr (the default): none.
using CcdObserver = void (*)(bool edge_edge, const std::array<Vec3, 8>& q);
void set_ccd_observer(CcdObserver observer);

/// Earliest time of impact in [0, 1], or none. The time is exact up to its rounding to a
/// double: an irrational root is returned as the lower end of an isolating interval whose ends
/// round to the same double, a rational one as its nearest double toward zero.
std::optional<double> exact_vertex_face_toi(const std::array<Vec3, 8>& q);
std::optional<double> exact_edge_edge_toi(const std::array<Vec3, 8>& q);

}  // namespace tc
