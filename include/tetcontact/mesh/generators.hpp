// Mesh generators (structured, every shape centred at the origin) and transforms.
//
// Each generator fills a lattice of hexahedral cells, maps it onto the shape, and splits every
// hex into tetrahedra:
//   5  — one central tet and four corner tets, mirrored on alternate cells (conforming);
//   6  — Kuhn's split along the cell diagonal that points away from the body's centre
//        (mirror-symmetric about the centre planes, conforming);
//   12 — the paper's cube (Dobritsa et al., Fig. 2: one cube = 12 tets): a node at the cell centre,
//        each of the six faces cut along the diagonal through its even-parity corners, each
//        face triangle joined to the centre.
// Cylinder and sphere map the lattice with a blend between the identity at the centre and the
// radial projection at the surface. The map flattens the cells along the lattice's edges into
// wedges; the mirrored 6-split keeps every tet of those open (min dihedral angle 31.8° for a
// sphere, 24.4° for a cylinder, against 0.7° and 5.6° with the 12-split and worse with the
// 5-split), so curved shapes offer split 6 only.
#pragma once

#include <array>
#include <vector>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

enum class HexSplit { five = 5, six = 6, twelve = 12 };

/// Box with the given edge lengths, `cells` hexes along x, y, z.
TetMesh make_box(const Vec3& size, std::array<int, 3> cells, HexSplit split);

/// Plate of size (lx, ly, thickness), thickness along z, `cells_through_thickness` layers and
/// in-plane cells chosen to keep the hexes near cubic.
TetMesh make_plate(const Vec3& size, int cells_through_thickness, HexSplit split);

/// A plate fine under the shot and coarse towards its rim: in each in-plane direction, cells
/// of the through-thickness size h across a centred core `core` wide, then each `growth` times
/// the one before it out to the rim.
struct PlateGrading {
  double core = 0.0;    // m, the width of the uniform square at the plate's centre
  double growth = 1.2;  // > 1: the ratio of neighbouring cells outside the core
};
TetMesh make_plate(const Vec3& size, int cells_through_thickness, HexSplit split,
                   const PlateGrading& grading);

/// The node coordinates of one graded direction of a plate `width` wide, centred on 0 and
/// symmetric about it (a node at 0): 2·n_c cells of size h in the core (n_c = round(core / 2h),
/// at least 1), then on each side m cells of sizes f·h·growth^k, k = 1..m, with m and the
/// factor f chosen so that the last ends on the rim and f is nearest 1 (no graded cell below
/// h). Less than a cell h outside the core gives uniform cells of about h (an even count).
std::vector<double> graded_axis(double width, double h, double core, double growth);

/// Cylinder along z: `cells_across` cells across the diameter, `cells_axial` along the axis;
/// split must be 6.
TetMesh make_cylinder(double radius, double height, int cells_across, int cells_axial,
                      HexSplit split);

/// Grading toward one face centre of the lattice (a pole of a sphere, the centre of a
/// cylinder's end): cells there are `factor` times the uniform size (0 < factor ≤ 1), growing
/// smoothly away from it. `toward` is ±x, ±y or ±z (a unit axis).
struct Grading {
  Vec3 toward = Vec3::Zero();  // zero: uniform
  double factor = 1.0;
};

/// Sphere: `cells_across` cells across the diameter; split must be 6.
TetMesh make_sphere(double radius, int cells_across, HexSplit split, const Grading& grading = {});

void translate(TetMesh& mesh, const Vec3& offset);
/// Rotation by `radians` about `axis` (right-hand rule) through the origin.
void rotate(TetMesh& mesh, const Vec3& axis, double radians);
void scale(TetMesh& mesh, double factor);

/// Quality of a tet: minimum dihedral angle in degrees (a regular tet has 70.53°).
double min_dihedral_angle_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace tc
