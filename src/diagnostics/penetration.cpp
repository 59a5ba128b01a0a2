#include "tetcontact/diagnostics/penetration.hpp"
#include "tetcontact/model/persist.hpp"

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

// The body each boundary node (and particle) is inside, −1 for none: the search's "faces" are
// the tets of the bodies here (cells turned into particles are no longer cells), found on
// binding lists; a listed pair goes on to the exact test only when its boxes of now overlap,
// so each node takes the body of the first tet, in the pairs' (sorted) order, that holds it, as a
// fresh search would give.
std::vector<Index> PenetrationProbe::bodies_holding(const std::vector<Vec3>& x) {
  const Mesh& mesh = model_.mesh;
  const auto tet_box = [&](Index t, double margin) {
    const Tet& k = mesh.tets[t];
    return swept_box({&x[k[0]], &x[k[1]], &x[k[2]], &x[k[3]]}, margin);
  };
  if (!inside_lists_.holds(all_nodes_, x)) {
    const double reach = inside_lists_.reach();
    BroadphaseInput in;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      in.node_box.push_back(swept_box({&x[nodes_[i]]}, reach));
      in.node_id.push_back(nodes_[i]);
      in.node_body.push_back(node_body_[i]);
    }
    for (const Index t : in_tet_) {
      const Tet& k = mesh.tets[t];
      in.face_box.push_back(tet_box(t, reach));
      in.face_nodes.push_back({k[0], k[1], k[2]});
      in.face_body.push_back(mesh.tet_body[t]);
    }
    inside_lists_.set(broadphase_->find(in), all_nodes_, x);
    ++searches_;
  }
  // The exact tests of the pairs on the threads.
  const Candidates& inside = inside_lists_.lists();
  std::vector<char> holds(inside.node_face.size());
  parallel::for_each(inside.node_face.size(), [&](std::size_t k) {
    const auto& [ni, ti] = inside.node_face[k];
    const Vec3& p = x[nodes_[ni]];
    const Tet& t = mesh.tets[in_tet_[ti]];
    holds[k] = boxes_overlap(swept_box({&p}, 0.0), tet_box(in_tet_[ti], 0.0)) &&
               exact_point_in_tet(p, x[t[0]], x[t[1]], x[t[2]], x[t[3]]);
  });
  std::vector<Index> inside_body(x.size(), -1);
  for (std::size_t k = 0; k < holds.size(); ++k) {
    const Index node = nodes_[inside.node_face[k].first];
    if (holds[k] && inside_body[node] < 0)
      inside_body[node] = mesh.tet_body[in_tet_[inside.node_face[k].second]];
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

// Boundary edges of one body crossing boundary faces of another, and the deepest crossing; the
// pairs from binding lists, each going on only when its boxes of now overlap.
void PenetrationProbe::measure_crossings(const std::vector<Vec3>& x, Penetration& r) {
  const auto edge_box = [&](std::size_t e, double margin) {
    return swept_box({&x[edges_[e][0]], &x[edges_[e][1]]}, margin);
  };
  const auto face_box = [&](std::size_t f, double margin) {
    const Face& k = faces_[f];
    return swept_box({&x[k[0]], &x[k[1]], &x[k[2]]}, margin);
  };
  if (!cross_lists_.holds(nodes_, x)) {
    const double reach = cross_lists_.reach();
    BroadphaseInput cross;
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      cross.node_box.push_back(edge_box(e, reach));
      cross.node_id.push_back(edges_[e][0]);
      cross.node_body.push_back(edge_body_[e]);
    }
    for (std::size_t f = 0; f < faces_.size(); ++f) {
      cross.face_box.push_back(face_box(f, reach));
      cross.face_nodes.push_back(faces_[f]);
      cross.face_body.push_back(face_body_[f]);
    }
    cross_lists_.set(broadphase_->find(cross), nodes_, x);
    ++searches_;
  }
  const Candidates& pairs = cross_lists_.lists();
  // Each pair on the threads: −1 when the edge does not cross the face, else the crossing's
  // depth; then counted and maximised in order.
  std::vector<double> crossing(pairs.node_face.size(), -1.0);
  parallel::for_each(pairs.node_face.size(), [&](std::size_t pair) {
    const auto& [e, f] = pairs.node_face[pair];
    const Face& k = faces_[f];
    if (!boxes_overlap(edge_box(e, 0.0), face_box(f, 0.0))) return;
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

// The primitives as they are now (fracture changes them): when they differ from the last
// call's, the binding lists are found anew.
bool PenetrationProbe::primitives_changed(const std::vector<Vec3>& x,
                                          const std::vector<Surface>& surfaces,
                                          const std::vector<Damage>& damage, Index first_particle) {
  std::vector<Index> nodes, node_body, edge_body, face_body, in_tet;
  std::vector<Edge> edges;
  std::vector<Face> faces;
  std::vector<double> body_h;
  for (const Surface& s : surfaces) {
    for (Index n : s.nodes) nodes.push_back(n), node_body.push_back(s.body);
    for (const Edge& e : s.edges) edges.push_back(e), edge_body.push_back(s.body);
    for (const Face& f : s.faces) faces.push_back(f), face_body.push_back(s.body);
    body_h.push_back(s.mean_edge_length);
  }
  // Particles are points of no body: inside any body counts.
  for (Index p = first_particle; p < static_cast<Index>(x.size()); ++p)
    nodes.push_back(p), node_body.push_back(-1);
  for (Index t = 0; t < model_.mesh.tet_count(); ++t)
    if (damage.empty() || damage[t] != Damage::particle) in_tet.push_back(t);
  const bool changed = nodes != nodes_ || node_body != node_body_ || edges != edges_ ||
                       faces != faces_ || in_tet != in_tet_ || all_nodes_.size() != x.size();
  if (!changed) return false;
  nodes_ = std::move(nodes), node_body_ = std::move(node_body);
  edges_ = std::move(edges), edge_body_ = std::move(edge_body);
  faces_ = std::move(faces), face_body_ = std::move(face_body);
  body_h_ = std::move(body_h);
  in_tet_ = std::move(in_tet);
  all_nodes_.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) all_nodes_[i] = static_cast<Index>(i);
  const double reach = binding_reach(surfaces);
  inside_lists_ = BindingLists(reach);
  cross_lists_ = BindingLists(reach);
  return true;
}

Penetration PenetrationProbe::measure(const std::vector<Vec3>& x,
                                      const std::vector<Surface>& surfaces,
                                      const std::vector<Damage>& damage, Index first_particle) {
  primitives_changed(x, surfaces, damage, first_particle);
  Penetration r;
  r.node_depth.assign(x.size(), 0.0);
  const Mesh& mesh = model_.mesh;
  if (mesh.bodies.size() < 2 && static_cast<Index>(x.size()) == first_particle) return r;

  const std::vector<Index> inside_body = bodies_holding(x);
  measure_depths(x, inside_body, first_particle, r);
  measure_crossings(x, r);
  return r;
}

void persist(Archive& ar, Penetration& p) {
  ar(p.nodes_inside, p.max_depth, p.max_depth_over_h, p.crossings, p.max_crossing_depth,
     p.particles_inside, p.max_particle_depth, p.node_depth, p.deepest_node_body, p.deepest_in_body,
     p.crossing_edge_body, p.crossing_face_body);
}

void PenetrationProbe::persist(Archive& ar) {
  ar.section("penetration");
  inside_lists_.persist(ar);
  cross_lists_.persist(ar);
  ar(searches_, all_nodes_, in_tet_, nodes_, node_body_, edges_, edge_body_, faces_, face_body_);
}

}  // namespace tc
