#include "tetcontact/mesh/surface.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "tetcontact/mesh/symmetry.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {
namespace {

struct FaceKey {
  Face sorted;    // sorted node triple: identifies the face
  Face oriented;  // as seen from its tet (outward)
  Index tet;
  bool operator<(const FaceKey& o) const {
    return sorted != o.sorted ? sorted < o.sorted : tet < o.tet;
  }
};

Face sorted_face(Face f) {
  std::sort(f.begin(), f.end());
  return f;
}

// A face with every node on one of the mesh's symmetry planes.
bool on_symmetry_plane(const Mesh& mesh, const Face& f) {
  return std::any_of(mesh.symmetry.begin(), mesh.symmetry.end(), [&](const SymmetryPlane& p) {
    return on_plane(mesh.x[f[0]], p) && on_plane(mesh.x[f[1]], p) && on_plane(mesh.x[f[2]], p);
  });
}

// A surface's boundary nodes, edges and node→faces adjacency from its faces (s.nodes and s.edges
// empty). slot_of: −1 for every mesh node, and so again on return.
void finish_surface(Surface& s, std::vector<Index>& slot_of) {
  // Boundary nodes and edges, sorted and each once: nodes marked over the range the faces
  // span, edges bucketed by their lower node (each bucket a few, sorted in place); no sort
  // of the whole surface.
  if (!s.faces.empty()) {
    Index lo = s.faces[0][0], hi = lo;
    for (const Face& f : s.faces)
      for (const Index v : f) lo = std::min(lo, v), hi = std::max(hi, v);
    const std::size_t span = static_cast<std::size_t>(hi - lo) + 1;
    std::vector<Index> start(span + 1, 0);
    for (const Face& f : s.faces)
      for (int e = 0; e < 3; ++e) ++start[std::min(f[e], f[(e + 1) % 3]) - lo + 1];
    for (std::size_t i = 0; i < span; ++i) start[i + 1] += start[i];
    std::vector<Index> upper(start.back());
    std::vector<Index> fill(start.begin(), start.end() - 1);
    for (const Face& f : s.faces)
      for (int e = 0; e < 3; ++e) {
        const Index a = f[e], c = f[(e + 1) % 3];
        upper[fill[std::min(a, c) - lo]++] = std::max(a, c);
      }
    std::vector<char> on(span, 0);
    for (const Face& f : s.faces)
      for (const Index v : f) on[v - lo] = 1;
    for (std::size_t i = 0; i < span; ++i) {
      if (on[i]) s.nodes.push_back(lo + static_cast<Index>(i));
      const auto b = upper.begin() + start[i], e = upper.begin() + start[i + 1];
      std::sort(b, e);
      for (auto it = b; it != e; ++it)
        if (it == b || *it != *(it - 1)) s.edges.push_back({lo + static_cast<Index>(i), *it});
    }
  }

  // node→faces in CSR form (each node's slot in s.nodes looked up in `slot_of`, cleared
  // at the end).
  s.node_face_offsets.assign(s.nodes.size() + 1, 0);
  for (std::size_t i = 0; i < s.nodes.size(); ++i) slot_of[s.nodes[i]] = static_cast<Index>(i);
  const auto slot = [&](Index node) { return static_cast<std::size_t>(slot_of[node]); };
  for (const Face& f : s.faces)
    for (Index v : f) ++s.node_face_offsets[slot(v) + 1];
  for (std::size_t i = 0; i < s.nodes.size(); ++i)
    s.node_face_offsets[i + 1] += s.node_face_offsets[i];
  s.node_faces.resize(s.node_face_offsets.back());
  std::vector<Index> fill(s.node_face_offsets.begin(), s.node_face_offsets.end() - 1);
  for (Index fi = 0; fi < static_cast<Index>(s.faces.size()); ++fi)
    for (Index v : s.faces[fi]) s.node_faces[fill[slot(v)]++] = fi;
  for (const Index n : s.nodes) slot_of[n] = -1;
}

}  // namespace

TetNeighbours tet_neighbours(const Mesh& mesh) {
  TetNeighbours nb(mesh.tets.size(), {k_no_tet, k_no_tet, k_no_tet, k_no_tet});
  for (Index b = 0; b < static_cast<Index>(mesh.bodies.size()); ++b) {
    const BodyRange& r = mesh.bodies[b];
    // Faces shared by two tets appear twice among the faces of the body's tets.
    std::vector<FaceKey> keys;
    keys.reserve(4 * static_cast<std::size_t>(r.tet_count()));
    for (Index t = r.tet_begin; t < r.tet_end; ++t) {
      const Tet& k = mesh.tets[t];
      for (int i = 0; i < 4; ++i) {
        const auto& lf = k_tet_faces[i];
        keys.push_back({sorted_face({k[lf[0]], k[lf[1]], k[lf[2]]}), {i, 0, 0}, t});
      }
    }
    std::sort(keys.begin(), keys.end());
    for (std::size_t i = 0; i < keys.size();) {
      std::size_t j = i + 1;
      while (j < keys.size() && keys[j].sorted == keys[i].sorted) ++j;
      if (j - i == 1 && on_symmetry_plane(mesh, keys[i].sorted)) {
        nb[keys[i].tet][keys[i].oriented[0]] = k_mirror_tet;
      } else if (j - i == 2) {
        nb[keys[i].tet][keys[i].oriented[0]] = keys[i + 1].tet;
        nb[keys[i + 1].tet][keys[i + 1].oriented[0]] = keys[i].tet;
      } else if (j - i > 2) {
        std::ostringstream os;
        os << "body '" << r.name << "': face (" << keys[i].sorted[0] - r.node_begin << ", "
           << keys[i].sorted[1] - r.node_begin << ", " << keys[i].sorted[2] - r.node_begin
           << ") is shared by " << (j - i) << " tets (first tet " << keys[i].tet - r.tet_begin
           << "); a conforming mesh shares a face between at most two";
        throw MeshError(os.str());
      }
      i = j;
    }
  }
  return nb;
}

std::vector<Surface> build_surfaces(const Mesh& mesh) {
  return build_surfaces(mesh, tet_neighbours(mesh), {});
}

std::vector<EdgeLengths> body_edge_lengths(const Mesh& mesh) {
  std::vector<EdgeLengths> lengths;
  for (const BodyRange& r : mesh.bodies) {
    EdgeLengths l;
    double edge_sum = 0.0;
    std::size_t edge_count = 0;
    for (Index t = r.tet_begin; t < r.tet_end; ++t) {
      const Tet& k = mesh.tets[t];
      for (const auto& le : k_tet_edges) {
        const double len = (mesh.x[k[le[0]]] - mesh.x[k[le[1]]]).norm();
        edge_sum += len;  // interior edges are counted once per tet that holds them
        l.max = std::max(l.max, len);
        ++edge_count;
      }
    }
    l.mean = edge_count ? edge_sum / static_cast<double>(edge_count) : 0.0;
    lengths.push_back(l);
  }
  return lengths;
}

std::vector<Surface> build_surfaces(const Mesh& mesh, const TetNeighbours& neighbours,
                                    const std::vector<char>& removed) {
  return build_surfaces(mesh, neighbours, removed, body_edge_lengths(mesh));
}

std::vector<Surface> build_surfaces(const Mesh& mesh, const TetNeighbours& neighbours,
                                    const std::vector<char>& removed,
                                    const std::vector<EdgeLengths>& lengths) {
  const auto gone = [&](Index t) { return !removed.empty() && removed[t]; };
  std::vector<Surface> surfaces;
  surfaces.reserve(mesh.bodies.size());
  std::vector<Index> slot_of(mesh.x.size(), -1);  // a surface node's index in its surface
  for (Index b = 0; b < static_cast<Index>(mesh.bodies.size()); ++b) {
    const BodyRange& r = mesh.bodies[b];
    Surface s;
    s.body = b;
    s.mean_edge_length = lengths[b].mean;  // of the whole body, removed tets included
    s.max_edge_length = lengths[b].max;

    // A boundary face is a face of a present tet with no present tet across it; faces are
    // listed in the order of their sorted node triples. The tets are read on the threads (each
    // block its own keys, joined in block order); the keys are then bucketed by their lowest
    // node and each bucket (a few faces) sorted.
    const std::size_t body_tets = static_cast<std::size_t>(r.tet_count());
    std::vector<std::vector<FaceKey>> found(
        parallel::block_count(body_tets, parallel::k_light_block));
    parallel::for_blocks(
        body_tets,
        [&](std::size_t blk, std::size_t begin, std::size_t end) {
          for (std::size_t u = begin; u < end; ++u) {
            const Index t = r.tet_begin + static_cast<Index>(u);
            if (gone(t)) continue;
            const Tet& k = mesh.tets[t];
            for (int i = 0; i < 4; ++i) {
              const Index other = neighbours[t][i];
              if (other == k_mirror_tet || (other >= 0 && !gone(other))) continue;
              const auto& lf = k_tet_faces[i];
              const Face f{k[lf[0]], k[lf[1]], k[lf[2]]};
              found[blk].push_back({sorted_face(f), f, t});
            }
          }
        },
        parallel::k_light_block);
    std::size_t count = 0;
    Index lowest = 0, highest = -1;
    for (const auto& keys : found)
      for (const FaceKey& key : keys) {
        lowest = count == 0 ? key.sorted[0] : std::min(lowest, key.sorted[0]);
        highest = std::max(highest, key.sorted[0]);
        ++count;
      }
    std::vector<FaceKey> keys(count);
    if (count > 0) {
      std::vector<std::size_t> at(static_cast<std::size_t>(highest - lowest) + 2, 0);
      for (const auto& block : found)
        for (const FaceKey& key : block) ++at[key.sorted[0] - lowest + 1];
      for (std::size_t i = 1; i < at.size(); ++i) at[i] += at[i - 1];
      std::vector<std::size_t> next(at.begin(), at.end() - 1);
      for (const auto& block : found)
        for (const FaceKey& key : block) keys[next[key.sorted[0] - lowest]++] = key;
      for (std::size_t i = 0; i + 1 < at.size(); ++i)
        if (at[i + 1] - at[i] > 1)
          std::sort(keys.begin() + static_cast<std::ptrdiff_t>(at[i]),
                    keys.begin() + static_cast<std::ptrdiff_t>(at[i + 1]));
    }
    s.faces.reserve(count);
    s.face_tet.reserve(count);
    for (const FaceKey& key : keys) {
      s.faces.push_back(key.oriented);
      s.face_tet.push_back(key.tet);
    }

    finish_surface(s, slot_of);
    surfaces.push_back(std::move(s));
  }
  return surfaces;
}

// Per body that lost a tet: its faces whose tet is gone leave; each face of a present tet
// toward a lost one joins (it was interior: no face listed it); the two, each in the order of
// the sorted node triples (then the tet), merged in that order, which is build_surfaces' order.
void update_surfaces(const Mesh& mesh, const TetNeighbours& neighbours,
                     const std::vector<char>& removed, const std::vector<Index>& gone,
                     std::vector<Surface>& surfaces) {
  if (gone.empty()) return;
  if (surfaces.size() != mesh.bodies.size())
    throw std::logic_error("update_surfaces: one surface a body, in the bodies' order");
  std::vector<std::vector<FaceKey>> exposed(mesh.bodies.size());
  std::vector<char> touched(mesh.bodies.size(), 0);
  for (const Index t : gone) {
    touched[mesh.tet_body[t]] = 1;
    for (int i = 0; i < 4; ++i) {
      const Index o = neighbours[t][i];
      if (o < 0 || removed[o]) continue;
      const auto& across = neighbours[o];
      const auto j = std::find(across.begin(), across.end(), t) - across.begin();
      const Tet& k = mesh.tets[o];
      const auto& lf = k_tet_faces[static_cast<std::size_t>(j)];
      const Face f{k[lf[0]], k[lf[1]], k[lf[2]]};
      exposed[mesh.tet_body[o]].push_back({sorted_face(f), f, o});
    }
  }
  std::vector<Index> slot_of(mesh.x.size(), -1);
  for (std::size_t b = 0; b < surfaces.size(); ++b) {
    if (!touched[b]) continue;
    Surface& s = surfaces[b];
    std::vector<FaceKey>& joining = exposed[b];
    std::sort(joining.begin(), joining.end());
    std::vector<Face> faces;
    std::vector<Index> face_tet;
    faces.reserve(s.faces.size() + joining.size());
    face_tet.reserve(s.faces.size() + joining.size());
    const auto take = [&](const FaceKey& key) {
      faces.push_back(key.oriented);
      face_tet.push_back(key.tet);
    };
    std::size_t next = 0;
    for (std::size_t f = 0; f < s.faces.size(); ++f) {
      if (removed[s.face_tet[f]]) continue;
      const FaceKey kept{sorted_face(s.faces[f]), s.faces[f], s.face_tet[f]};
      while (next < joining.size() && joining[next] < kept) take(joining[next++]);
      take(kept);
    }
    while (next < joining.size()) take(joining[next++]);
    s.faces = std::move(faces);
    s.face_tet = std::move(face_tet);
    s.nodes.clear();
    s.edges.clear();
    finish_surface(s, slot_of);
  }
}

double smallest_mean_edge(const std::vector<Surface>& surfaces) {
  double h = 0.0;
  for (const Surface& s : surfaces)
    if (s.mean_edge_length > 0.0)
      h = h > 0.0 ? std::min(h, s.mean_edge_length) : s.mean_edge_length;
  return h;
}

Vec3 face_normal(const Face& f, const std::vector<Vec3>& x) {
  const Vec3 n = (x[f[1]] - x[f[0]]).cross(x[f[2]] - x[f[0]]);
  const double len = n.norm();
  return len > 0.0 ? Vec3(n / len) : Vec3::Zero();
}

std::vector<Vec3> node_normals(const Surface& s, const std::vector<Vec3>& x) {
  std::vector<Vec3> normals(s.nodes.size(), Vec3::Zero());
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    Vec3 sum = Vec3::Zero();
    for (Index k = s.node_face_offsets[i]; k < s.node_face_offsets[i + 1]; ++k)
      sum += face_normal(s.faces[s.node_faces[k]], x);
    const double len = sum.norm();
    if (len > 0.0) normals[i] = sum / len;
  }
  return normals;
}

Index non_manifold_edges(const Surface& s) {
  std::vector<Edge> all;
  all.reserve(3 * s.faces.size());
  for (const Face& f : s.faces)
    for (int e = 0; e < 3; ++e) {
      Index a = f[e], c = f[(e + 1) % 3];
      all.push_back({std::min(a, c), std::max(a, c)});
    }
  std::sort(all.begin(), all.end());
  Index bad = 0;
  for (std::size_t i = 0; i < all.size();) {
    std::size_t j = i + 1;
    while (j < all.size() && all[j] == all[i]) ++j;
    bad += (j - i != 2);
    i = j;
  }
  return bad;
}

}  // namespace tc
