// Unstructured meshes by Delaunay refinement (CGAL's Mesh_3, confined to src/mesh/delaunay.cpp).
//
// A lattice can be graded toward a point only so far before its cells shear (the sphere's
// `refine_factor`); a contact patch much smaller than the body (Hertz: radius 0.16 mm on a 10 mm
// sphere) needs cells there some 25 times smaller than in the bulk. Delaunay refinement meets a
// size field instead: cells near the refinement point of size `refine_size`, growing linearly
// with the distance d from it, capped at `cell_size`:
//   h(x) = min(cell_size, refine_size + growth · d(x)),
// where h bounds the circumradius of cells and surface triangles. Slivers are removed by
// exudation (no Lloyd smoothing: CGAL's is not reproducible run to run). Sequential meshing
// with CGAL's fixed seeds gives the same mesh every run (tested).
#pragma once

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

struct BallSizing {
  double cell_size = 0.0;             // m, the largest cell (circumradius bound)
  Vec3 refine_toward = Vec3::Zero();  // direction of the refinement point on the surface; 0: none
  double refine_size = 0.0;           // m, cells at the refinement point
  double growth = 0.15;               // dimensionless: cell size gained per unit distance
};

/// Ball of radius `radius` centred at the origin, meshed by Delaunay refinement with the size
/// field above. Surface nodes lie on the sphere (projected to it after meshing); every tet is
/// positively oriented. Throws std::invalid_argument for sizes out of range (each > 0,
/// refine_size ≤ cell_size ≤ radius, 0 < growth ≤ 1, radius / refine_size ≤ 10⁴).
TetMesh mesh_ball(double radius, const BallSizing& sizing);

}  // namespace tc
