#include "tetcontact/mesh/symmetry.hpp"

#include <algorithm>
#include <sstream>

namespace tc {

std::string plane_name(const SymmetryPlane& plane) {
  std::ostringstream os;
  os << "xyz"[plane.axis] << " = " << plane.at;
  return os.str();
}

void cut_at_plane(TetMesh& mesh, const SymmetryPlane& plane, const std::string& body_name) {
  if (mesh.x.empty()) return;
  Vec3 lo = mesh.x[0], hi = lo;
  for (const Vec3& p : mesh.x) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double tol = 1e-9 * (hi - lo).norm();
  const int a = plane.axis;
  std::vector<Tet> kept;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const Tet& k = mesh.tets[t];
    bool above = true, below = true;  // every node on the kept side; every node on the other
    for (const Index n : k) {
      above = above && mesh.x[n][a] >= plane.at - tol;
      below = below && mesh.x[n][a] <= plane.at + tol;
    }
    if (above && !below) {
      kept.push_back(k);
    } else if (!above && !below) {
      std::ostringstream os;
      os << "body '" << body_name << "': tet " << t << " straddles the symmetry plane "
         << plane_name(plane)
         << "; the mesh needs a node layer on the plane (an even number of cells across it, "
            "centred on it)";
      throw MeshError(os.str());
    }
  }
  if (kept.empty())
    throw MeshError("body '" + body_name +
                    "': no tet lies on the positive side of the symmetry plane " +
                    plane_name(plane));
  mesh.tets = std::move(kept);
  for (Vec3& p : mesh.x)
    if (std::abs(p[a] - plane.at) <= tol) p[a] = plane.at;
  compact_nodes(mesh);
}

Vec3 mirror_image(Vec3 x, const std::vector<SymmetryPlane>& planes, int k) {
  for (std::size_t i = 0; i < planes.size(); ++i)
    if ((k >> i) & 1) x[planes[i].axis] = 2.0 * planes[i].at - x[planes[i].axis];
  return x;
}

Vec3 mirror_direction(Vec3 d, const std::vector<SymmetryPlane>& planes, int k) {
  for (std::size_t i = 0; i < planes.size(); ++i)
    if ((k >> i) & 1) d[planes[i].axis] = -d[planes[i].axis];
  return d;
}

std::vector<Vec3> mirror_images(const Vec3& x, const std::vector<SymmetryPlane>& planes) {
  std::vector<Vec3> images;
  for (int k = 0; k < multiplicity(planes); ++k) images.push_back(mirror_image(x, planes, k));
  return images;
}

}  // namespace tc
