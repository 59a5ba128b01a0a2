// The floating-point swept vertex–face test the contact stage used before the exact CCD: kept
// only as the comparison `tetcontact stress` prints beside the exact answers (its
// disagreements on degenerate families are why the engine uses exact_ccd.hpp). No stage of
// the engine calls it.
#pragma once

#include <optional>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

/// Continuous vertex–face test, every point moving linearly over t ∈ [0, 1]: the earliest t
/// at which p(t) lies in the triangle (a(t), b(t), c(t)). The coplanarity condition
///   det[b − a, c − a, p − a](t) = 0
/// is a cubic in t (Dobritsa et al. eq. 13 for a vertex and a face); each root in [0, 1] is checked
/// for the point lying inside the triangle. Floating point with a relative tolerance of 1e-12
/// on the barycentric test.
std::optional<double> vertex_face_ccd(const Vec3& p0, const Vec3& a0, const Vec3& b0,
                                      const Vec3& c0, const Vec3& p1, const Vec3& a1,
                                      const Vec3& b1, const Vec3& c1);

}  // namespace tc
