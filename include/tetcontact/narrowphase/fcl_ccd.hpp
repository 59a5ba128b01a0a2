// FCL 0.7's cubic CCD (Intersect::intersect_EE / intersect_VF, Newton refinement on), for
// comparison only: it uses absolute thresholds and misses real collisions. The query order is
// the one of exact_ccd.hpp. FCL is confined to src/narrowphase/fcl_ccd.cpp.
#pragma once

#include <array>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

bool fcl_vertex_face_ccd(const std::array<Vec3, 8>& q);
bool fcl_edge_edge_ccd(const std::array<Vec3, 8>& q);

}  // namespace tc
