// An independent exact CCD oracle on CGAL (the design's "CGAL confirms at the root"), sharing no
// code with exact_ccd.cpp: the coordinates become CGAL::Gmpz integers (times one power of two),
// the coplanarity determinant (Dobritsa et al. eq. 13) a CGAL polynomial, its real roots in [0, 1]
// are isolated by CGAL's algebraic kernel (Algebraic_kernel_d_1: Bitstream Descartes), and at each
// root the kernel gives the exact sign of the inside test's polynomials. CGAL only in
// cgal_ccd.cpp.
//
// It decides every query except three degenerate kinds, where it answers "undecided" (nullopt):
// motions coplanar for the whole step (the determinant is identically zero), a face that is
// degenerate (its corners collinear) at a root, and edges parallel at a root. Those are left to
// the second exact reference of the tests (tests/narrowphase/reference_ccd.hpp).
#pragma once

#include <array>
#include <optional>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

/// q as in exact_ccd.hpp: the four points at t = 0, then at t = 1.
std::optional<bool> cgal_vertex_face_ccd(const std::array<Vec3, 8>& q);
std::optional<bool> cgal_edge_edge_ccd(const std::array<Vec3, 8>& q);

}  // namespace tc
