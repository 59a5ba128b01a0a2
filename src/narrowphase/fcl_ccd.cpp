// FCL's cubic CCD behind our small header; the only narrow-phase file that includes FCL.
#include "tetcontact/narrowphase/fcl_ccd.hpp"

#include <fcl/narrowphase/detail/traversal/collision/intersect.h>

namespace tc {

using FclIntersect = fcl::detail::Intersect<double>;

bool fcl_vertex_face_ccd(const std::array<Vec3, 8>& q) {
  double t = 0;
  fcl::Vector3<double> p;
  // FCL's order: the face's corners, then the vertex.
  return FclIntersect::intersect_VF(q[1], q[2], q[3], q[0], q[5], q[6], q[7], q[4], &t, &p);
}

bool fcl_edge_edge_ccd(const std::array<Vec3, 8>& q) {
  double t = 0;
  fcl::Vector3<double> p;
  return FclIntersect::intersect_EE(q[0], q[1], q[2], q[3], q[4], q[5], q[6], q[7], &t, &p);
}

}  // namespace tc
