#include "tetcontact/diagnostics/penetration.hpp"

#include <algorithm>

#include "tetcontact/narrowphase/vertex_face.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {

void keep_largest(Penetration& m, const Penetration& p) {
  m.nodes_inside = std::max(m.nodes_inside, p.nodes_inside);
  m.max_depth = std::max(m.max_depth, p.max_depth);
  m.max_depth_over_h = std::max(m.max_depth_over_h, p.max_depth_over_h);
  m.crossings = std::max(m.crossings, p.crossings);
  m.max_crossing_depth = std::max(m.max_crossing_depth, p.max_crossing_depth);
  m.particles_inside = std::max(m.particles_inside, p.particles_inside);
  m.max_particle_depth = std::max(m.max_particle_depth, p.max_particle_depth);
}

PenetrationProbe::PenetrationProbe(const Model& model)
    : model_(model), broadphase_(make_broadphase("grid")) {}

Penetration PenetrationProbe::measure(const State& st) {
  return measure(st.x, st.surfaces, st.damage, st.first_particle);
}

Penetration PenetrationProbe::measure(const std::vector<Vec3>& x) {
  return measure(x, model_.surfaces, {}, static_cast<Index>(x.size()));
}

// The body each boundary node (and particle) is inside, −1 for none: the broadphase's "faces"
// are the tets of the bodies here (cells turned into particles are no longer cells).
std::vector<Index> PenetrationProbe::bodies_holding(const std::vector<Vec3>& x,
                                                    const std::vector<Damage>& damage) {
  const Mesh& mesh = model_.mesh;
  BroadphaseInput in;
  std::vector<Index> in_tet;  // the tet of each of its "faces"
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    in.node_box.push_back(swept_box({&x[nodes_[i]]}, 0.0));
    in.node_id.push_back(nodes_[i]);
    in.node_body.push_back(node_body_[i]);
  }
  for (Index t = 0; t < mesh.tet_count(); ++t) {
    if (!damage.empty() && damage[t] == Damage::particle) continue;  // no longer a cell
    const Tet& k = mesh.tets[t];
    in.face_box.push_back(swept_box({&x[k[0]], &x[k[1]], &x[k[2]], &x[k[3]]}, 0.0));
    in.face_nodes.push_back({k[0], k[1], k[2]});
    in.face_body.push_back(mesh.tet_body[t]);
    in_tet.push_back(t);
  }
  // The exact tests of the pairs on the threads; each node takes the body of the first tet in
  // the pairs' (sorted) order that holds it.
  const Candidates inside = broadphase_->find(in);
  std::vector<char> holds(inside.node_face.size());
  parallel::for_each(inside.node_face.size(), [&](std::size_t k) {
    const auto& [ni, ti] = inside.node_face[k];
    const Tet& t = mesh.tets[in_tet[ti]];
    holds[k] = exact_point_in_tet(x[nodes_[ni]], x[t[0]], x[t[1]], x[t[2]], x[t[3]]);
  });
  std::vector<Index> inside_body(x.size(), -1);
  for (std::size_t k = 0; k < holds.size(); ++k) {
    const Index node = nodes_[inside.node_face[k].first];
    if (holds[k] && inside_body[node] < 0)
      inside_body[node] = mesh.tet_body[in_tet[inside.node_face[k].second]];
  }

  return inside_body;
}

// The depth of each node inside a body: the distance to the nearest boundary face of the body
// it is in, within 2h (h that body's mean tet edge); the counts and maxima of nodes and
// particles inside.
void PenetrationProbe::measure_depths(const std::vector<Vec3>& x,
                                      const std::vector<Index>& inside_body, Index first_particle,
                                      Penetration& r) {
  BroadphaseInput near;
  std::vector<std::size_t> near_index;  // into nodes_
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Index node = nodes_[i];
    if (inside_body[node] < 0) continue;
    near_index.push_back(i);
    near.node_box.push_back(swept_box({&x[node]}, 2.0 * body_h_[inside_body[node]]));
    near.node_id.push_back(node);
    near.node_body.push_back(node_body_[i]);
  }
  if (!near.node_box.empty()) {
    for (std::size_t f = 0; f < faces_.size(); ++f) {
      const Face& k = faces_[f];
      near.face_box.push_back(swept_box({&x[k[0]], &x[k[1]], &x[k[2]]}, 0.0));
      near.face_nodes.push_back(k);
      near.face_body.push_back(face_body_[f]);
    }
    for (std::size_t i = 0; i < near.node_id.size(); ++i)
      r.node_depth[near.node_id[i]] = 2.0 * body_h_[inside_body[near.node_id[i]]];
    const Candidates close = broadphase_->find(near);
    std::vector<double> distance(close.node_face.size(), -1.0);  // −1: another body's face
    parallel::for_each(close.node_face.size(), [&](std::size_t p) {
      const auto& [ni, f] = close.node_face[p];
      const Index node = near.node_id[ni];
      if (face_body_[f] != inside_body[node]) return;
      const Face& k = faces_[f];
      distance[p] = exact_point_on_triangle(x[node], x[k[0]], x[k[1]], x[k[2]])
                        ? 0.0
                        : closest_point_on_triangle(x[node], x[k[0]], x[k[1]], x[k[2]]).distance;
    });
    for (std::size_t p = 0; p < distance.size(); ++p) {
      const Index node = near.node_id[close.node_face[p].first];
      if (distance[p] >= 0.0) r.node_depth[node] = std::min(r.node_depth[node], distance[p]);
    }
    for (std::size_t i = 0; i < near.node_id.size(); ++i) {
      const Index node = near.node_id[i];
      if (node >= first_particle) {
        r.particles_inside += r.node_depth[node] > 0.0;
        r.max_particle_depth = std::max(r.max_particle_depth, r.node_depth[node]);
        continue;
      }
      r.nodes_inside += r.node_depth[node] > 0.0;
      if (r.node_depth[node] > r.max_depth) {
        r.deepest_node_body = node_body_[near_index[i]];
        r.deepest_in_body = inside_body[node];
      }
      r.max_depth = std::max(r.max_depth, r.node_depth[node]);
      r.max_depth_over_h =
          std::max(r.max_depth_over_h, r.node_depth[node] / body_h_[inside_body[node]]);
    }
  }
}

// Boundary edges of one body crossing boundary faces of another, and the deepest crossing.
void PenetrationProbe::measure_crossings(const std::vector<Vec3>& x, Penetration& r) {
  BroadphaseInput cross;
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    cross.node_box.push_back(swept_box({&x[edges_[e][0]], &x[edges_[e][1]]}, 0.0));
    cross.node_id.push_back(edges_[e][0]);
    cross.node_body.push_back(edge_body_[e]);
  }
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    const Face& k = faces_[f];
    cross.face_box.push_back(swept_box({&x[k[0]], &x[k[1]], &x[k[2]]}, 0.0));
    cross.face_nodes.push_back(k);
    cross.face_body.push_back(face_body_[f]);
  }
  // Each pair on the threads: −1 when the edge does not cross the face, else the crossing's
  // depth; then counted and maximised in order.
  const Candidates pairs = broadphase_->find(cross);
  std::vector<double> crossing(pairs.node_face.size(), -1.0);
  parallel::for_each(pairs.node_face.size(), [&](std::size_t pair) {
    const auto& [e, f] = pairs.node_face[pair];
    const Face& k = faces_[f];
    if (exact_segment_crosses_triangle(x[edges_[e][0]], x[edges_[e][1]], x[k[0]], x[k[1]],
                                       x[k[2]])) {
      // Depth of the crossing: the shorter of the two moves that undo it, sliding the edge out
      // of the face (the crossing point's distance to the face's boundary: small for an edge
      // grazing the face's rim) or pulling the edge's nearer end back to the face's plane
      // (small for an edge barely poking through).
      const Vec3 &p = x[edges_[e][0]], &q = x[edges_[e][1]];
      const Vec3 n = (x[k[1]] - x[k[0]]).cross(x[k[2]] - x[k[0]]);
      const double dp = (p - x[k[0]]).dot(n), dq = (q - x[k[0]]).dot(n);
      const Vec3 at = p + (dp / (dp - dq)) * (q - p);
      double inside = std::min(std::abs(dp), std::abs(dq)) / n.norm();
      for (int s = 0; s < 3; ++s) {
        const SegmentPoints sp = closest_points_on_segments(at, at, x[k[s]], x[k[(s + 1) % 3]]);
        inside = std::min(inside, (sp.on_a - sp.on_b).norm());
      }
      crossing[pair] = inside;
    }
  });
  for (std::size_t pair = 0; pair < crossing.size(); ++pair)
    if (crossing[pair] >= 0.0) {
      ++r.crossings;
      if (r.crossing_edge_body < 0 || crossing[pair] > r.max_crossing_depth) {
        r.crossing_edge_body = edge_body_[pairs.node_face[pair].first];
        r.crossing_face_body = face_body_[pairs.node_face[pair].second];
      }
      r.max_crossing_depth = std::max(r.max_crossing_depth, crossing[pair]);
    }
}

Penetration PenetrationProbe::measure(const std::vector<Vec3>& x,
                                      const std::vector<Surface>& surfaces,
                                      const std::vector<Damage>& damage, Index first_particle) {
  // The surfaces as they are now (fracture changes them).
  nodes_.clear(), node_body_.clear(), edges_.clear(), edge_body_.clear();
  faces_.clear(), face_body_.clear(), body_h_.clear();
  for (const Surface& s : surfaces) {
    for (Index n : s.nodes) nodes_.push_back(n), node_body_.push_back(s.body);
    for (const Edge& e : s.edges) edges_.push_back(e), edge_body_.push_back(s.body);
    for (const Face& f : s.faces) faces_.push_back(f), face_body_.push_back(s.body);
    body_h_.push_back(s.mean_edge_length);
  }
  // Particles are points of no body: inside any body counts.
  for (Index p = first_particle; p < static_cast<Index>(x.size()); ++p)
    nodes_.push_back(p), node_body_.push_back(-1);

  Penetration r;
  r.node_depth.assign(x.size(), 0.0);
  const Mesh& mesh = model_.mesh;
  if (mesh.bodies.size() < 2 && static_cast<Index>(x.size()) == first_particle) return r;

  const std::vector<Index> inside_body = bodies_holding(x, damage);
  measure_depths(x, inside_body, first_particle, r);
  measure_crossings(x, r);
  return r;
}

}  // namespace tc
