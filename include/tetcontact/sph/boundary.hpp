// A body's surface as the SPH kernel sees it: the integrals of the kernel over a face, with
// which a particle meets the bodies' faces through its kernel (sph.hpp, "the bodies' faces").
//
// For a body R and a particle at x, the kernel sums over the particles miss the neighbours R
// would be; by the divergence theorem, with n the outward unit normal of R's faces,
//
//   ∫_R ∇_x W(|x − x'|, h) dV' = −Σ_faces n_k Φ_k,      Φ_k = ∫_face W(|x − x'|, h) dS',
//
// exact for any shape of R (its faces out of the kernel's reach add nothing). The weights
// w_v = ∫_face W λ_v dS' / Φ (λ_v the face's barycentric coordinates) share out a force at the
// face's kernel-weighted point x_c = Σ w_v x_v among its nodes so that their moment is kept.
#pragma once

#include <array>

#include "tetcontact/mesh/mesh.hpp"
#include "tetcontact/parallel/lanes.hpp"

namespace tc::sph {

struct FaceKernel {
  double phi = 0.0;                        // Φ, 1/m
  std::array<double, 3> w{0.0, 0.0, 0.0};  // Σ w_v = 1 when Φ > 0
};

/// What of a triangle (a, b, c) does not depend on the particle: its box, unit normal n (right
/// hand), twice its area, its edges' unit directions, lengths and in-plane outward normals
/// ν = dir × n, and the barycentric coordinates' gradients. A stage that meets one face from
/// many particles computes it once per face.
struct FaceShape {
  std::array<Vec3, 3> corner;
  Vec3 lo, hi;
  Vec3 normal;                        // n (when twice_area > 0)
  double twice_area;                  // |(b − a) × (c − a)|
  std::array<Vec3, 3> dir, nu, grad;  // edge e from corner e to e + 1; grad: ∇λ_v
  std::array<double, 3> length;
};
FaceShape face_shape(const Vec3& a, const Vec3& b, const Vec3& c);

/// Φ and the weights of the triangle (a, b, c) for a particle at x with smoothing length h, as
/// sums over the triangle's edges (the divergence theorem in the face's plane): the kernel's
/// radial integral in closed form, along each edge six Gauss points per piece between the
/// kernel's knees; zero out of reach.
FaceKernel face_kernel(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, double h);
/// The same of the face's shape (face_shape(a, b, c)): the same doubles.
FaceKernel face_kernel(const Vec3& x, const FaceShape& face, double h);

/// How face_kernel evaluates its edges' Gauss points (parallel/lanes.hpp): one at a time
/// (`Lanes::scalar`, the reference), or in SIMD lanes. Sets it; returns the previous setting.
/// Lanes wider than widest_lanes() throw std::invalid_argument.
Lanes set_face_lanes(Lanes lanes);

/// By the centroid rule on n × n sub-triangles (the edges' sums' check).
FaceKernel face_kernel(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, double h, int n);

}  // namespace tc::sph
