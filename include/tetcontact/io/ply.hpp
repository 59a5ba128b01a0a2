// PLY triangle surfaces (ASCII or binary little/big endian): vertices and triangles;
// polygons are split into fans.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

struct PlyError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct TriangleSurface {
  std::vector<Vec3> x;
  std::vector<std::array<Index, 3>> triangles;
};

TriangleSurface read_ply(const std::string& path);

/// The unique vertex pairs of the triangles, sorted (a < b).
std::vector<std::array<Index, 2>> surface_edges(const TriangleSurface& s);

}  // namespace tc
