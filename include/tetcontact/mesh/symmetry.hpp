// Symmetry planes: a body symmetric about a coordinate plane is modelled by the half on the
// plane's positive side, and the whole is its union with the mirror image. The mesh is cut
// along the plane (every tet on one side of it: a conforming node layer on the plane); the
// faces left on the plane are interior faces of the whole (their neighbour is the tet's own
// mirror image), so they join no surface; nodes on the plane keep no normal velocity
// (the setup's constraint) and every other node and particle meets the plane as a frictionless
// rigid wall (what its mirror image would do to it). Measures of the whole count every
// item's mirror images (diagnostics/reference.cpp).
#pragma once

#include <string>
#include <vector>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

/// "x = 0.002" (the name of the plane in messages and summaries).
std::string plane_name(const SymmetryPlane& plane);

/// The part of one body's mesh on the plane's positive side: tets with every node at
/// x[axis] ≥ at − tol kept, those with every node at ≤ at + tol dropped (tol: 1e-9 of the
/// body's size), nodes within tol of the plane put on it exactly, unused nodes dropped. Throws
/// MeshError naming the body and the first tet that straddles the plane (its mesh has no node
/// layer there: an odd cell count across it), or when no tet is left.
void cut_at_plane(TetMesh& mesh, const SymmetryPlane& plane, const std::string& body_name);

/// Whether x lies on the plane (exactly: cut_at_plane puts the plane's nodes there, and their
/// normal velocity stays zero).
inline bool on_plane(const Vec3& x, const SymmetryPlane& plane) {
  return x[plane.axis] == plane.at;
}

/// Image k of a point: reflected across the planes whose bit is set in k (image 0: the point).
Vec3 mirror_image(Vec3 x, const std::vector<SymmetryPlane>& planes, int k);
/// Image k of a direction (a velocity, a normal): its components along those planes' normals
/// reversed.
Vec3 mirror_direction(Vec3 d, const std::vector<SymmetryPlane>& planes, int k);

/// The point and its mirror images across every plane and every combination of them
/// (2^planes points: mirror_image for k = 0, 1, …).
std::vector<Vec3> mirror_images(const Vec3& x, const std::vector<SymmetryPlane>& planes);

/// How many copies of the model make the whole: 2^planes.
inline int multiplicity(const std::vector<SymmetryPlane>& planes) {
  return 1 << planes.size();
}

}  // namespace tc
