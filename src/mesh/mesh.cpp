#include "tetcontact/mesh/mesh.hpp"

#include <cmath>
#include <sstream>

namespace tc {

OrientReport orient_tets(TetMesh& mesh, const std::string& body_name) {
  OrientReport report;
  const std::size_t m = mesh.tets.size();
  if (m == 0) throw MeshError("body '" + body_name + "': mesh has no tetrahedra");
  for (std::size_t t = 0; t < m; ++t)
    for (Index v : mesh.tets[t])
      if (v < 0 || static_cast<std::size_t>(v) >= mesh.x.size()) {
        std::ostringstream os;
        os << "body '" << body_name << "', tet " << t << ": node index " << v << " outside [0, "
           << mesh.x.size() << ")";
        throw MeshError(os.str());
      }

  std::vector<double> vol(m);
  double mean_abs = 0.0;
  std::size_t negative = 0;
  for (std::size_t t = 0; t < m; ++t) {
    const Tet& k = mesh.tets[t];
    vol[t] = tet_signed_volume(mesh.x[k[0]], mesh.x[k[1]], mesh.x[k[2]], mesh.x[k[3]]);
    if (!std::isfinite(vol[t])) {
      std::ostringstream os;
      os << "body '" << body_name << "', tet " << t << ": non-finite node coordinates";
      throw MeshError(os.str());
    }
    mean_abs += std::abs(vol[t]);
    negative += vol[t] < 0.0;
  }
  mean_abs /= static_cast<double>(m);

  // Degenerate first: a zero-volume tet has no orientation to fix.
  for (std::size_t t = 0; t < m; ++t)
    if (std::abs(vol[t]) <= 1e-12 * mean_abs) {
      std::ostringstream os;
      os << "body '" << body_name << "', tet " << t << ": zero volume (" << vol[t]
         << " m^3, body mean " << mean_abs << " m^3)";
      throw MeshError(os.str());
    }

  const bool flip = negative * 2 > m;  // the body's convention is the negative one
  for (std::size_t t = 0; t < m; ++t) {
    const bool is_negative = vol[t] < 0.0;
    if (is_negative != flip) {
      std::ostringstream os;
      os << "body '" << body_name << "', tet " << t << ": inverted element (signed volume "
         << (flip ? -vol[t] : vol[t]) << " m^3 against the body's orientation; " << m << " tets, "
         << (flip ? m - negative : negative) << " inverted)";
      throw MeshError(os.str());
    }
    if (flip) std::swap(mesh.tets[t][2], mesh.tets[t][3]);
  }
  report.flipped_all = flip;
  return report;
}

Index add_body(Mesh& mesh, const std::string& name, TetMesh body) {
  orient_tets(body, name);
  BodyRange range;
  range.name = name;
  range.node_begin = mesh.node_count();
  range.tet_begin = mesh.tet_count();
  const Index base = range.node_begin;
  const Index id = static_cast<Index>(mesh.bodies.size());
  mesh.x.insert(mesh.x.end(), body.x.begin(), body.x.end());
  for (Tet t : body.tets) {
    for (Index& v : t) v += base;
    mesh.tets.push_back(t);
  }
  range.node_end = mesh.node_count();
  range.tet_end = mesh.tet_count();
  mesh.tet_body.resize(mesh.tets.size(), id);
  mesh.node_body.resize(mesh.x.size(), id);
  mesh.bodies.push_back(range);
  return id;
}

std::vector<double> tet_volumes(const std::vector<Vec3>& x, const std::vector<Tet>& tets) {
  std::vector<double> v(tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const Tet& k = tets[t];
    v[t] = tet_signed_volume(x[k[0]], x[k[1]], x[k[2]], x[k[3]]);
  }
  return v;
}

double total_volume(const TetMesh& mesh) {
  double sum = 0.0;
  for (const Tet& k : mesh.tets)
    sum += tet_signed_volume(mesh.x[k[0]], mesh.x[k[1]], mesh.x[k[2]], mesh.x[k[3]]);
  return sum;
}

double body_volume(const Mesh& mesh, Index body, const std::vector<Vec3>& x) {
  const BodyRange& r = mesh.bodies.at(body);
  double sum = 0.0;
  for (Index t = r.tet_begin; t < r.tet_end; ++t) {
    const Tet& k = mesh.tets[t];
    sum += tet_signed_volume(x[k[0]], x[k[1]], x[k[2]], x[k[3]]);
  }
  return sum;
}

void compact_nodes(TetMesh& mesh) {
  // Keep the original node order (new index increases with the old one).
  std::vector<Index> map(mesh.x.size(), -1);
  for (const Tet& t : mesh.tets)
    for (Index v : t) map[v] = 0;
  std::vector<Vec3> x;
  for (std::size_t i = 0; i < map.size(); ++i)
    if (map[i] == 0) {
      map[i] = static_cast<Index>(x.size());
      x.push_back(mesh.x[i]);
    }
  for (Tet& t : mesh.tets)
    for (Index& v : t) v = map[v];
  mesh.x = std::move(x);
}

}  // namespace tc
