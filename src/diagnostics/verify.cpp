#include "tetcontact/diagnostics/verify.hpp"

#include <algorithm>

#include "tetcontact/diagnostics/penetration.hpp"
#include "tetcontact/narrowphase/exact_ccd.hpp"
#include "tetcontact/parallel/mpi.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {

StepVerifier::StepVerifier(const Mesh& mesh) : mesh_(mesh), broadphase_(make_broadphase("grid")) {}

// The primitives of the surfaces as they are now, and the particles as vertices of no body.
void StepVerifier::build(const std::vector<Surface>& surfaces, Index first_particle,
                         std::size_t nodes) {
  BroadphaseInput& in = input_;
  in = BroadphaseInput{};
  face_tet_.clear();
  edge_faces_.clear();
  for (const Surface& s : surfaces) {
    const Index face0 = static_cast<Index>(in.face_nodes.size());
    const Index edge0 = static_cast<Index>(in.edge_nodes.size());
    for (Index n : s.nodes) in.node_id.push_back(n), in.node_body.push_back(s.body);
    for (std::size_t f = 0; f < s.faces.size(); ++f) {
      in.face_nodes.push_back(s.faces[f]);
      in.face_body.push_back(s.body);
      face_tet_.push_back(s.face_tet[f]);
    }
    for (const Edge& e : s.edges) in.edge_nodes.push_back(e), in.edge_body.push_back(s.body);
    edge_faces_.resize(in.edge_nodes.size(), {-1, -1});
    for (std::size_t f = 0; f < s.faces.size(); ++f)
      for (int k = 0; k < 3; ++k) {
        Edge e{s.faces[f][k], s.faces[f][(k + 1) % 3]};
        if (e[0] > e[1]) std::swap(e[0], e[1]);
        const auto it = std::lower_bound(s.edges.begin(), s.edges.end(), e);
        if (it == s.edges.end() || *it != e) continue;
        auto& slots = edge_faces_[edge0 + (it - s.edges.begin())];
        (slots[0] < 0 ? slots[0] : slots[1]) = face0 + static_cast<Index>(f);
      }
  }
  for (Index p = first_particle; p < static_cast<Index>(nodes); ++p)
    in.node_id.push_back(p), in.node_body.push_back(-1);
  in.node_box.resize(in.node_id.size());
  in.face_box.resize(in.face_nodes.size());
  in.edge_box.resize(in.edge_nodes.size());
  lists_ = BindingLists(binding_reach(surfaces));
}

Verification StepVerifier::verify(const std::vector<Surface>& surfaces, const std::vector<Vec3>& x0,
                                  const std::vector<Vec3>& x1, Index first_particle) {
  return run(surfaces, x0, x1, first_particle, nullptr);
}

Verification StepVerifier::verify_again(const std::vector<Surface>& surfaces,
                                        const std::vector<Vec3>& x0, const std::vector<Vec3>& x1,
                                        Index first_particle, const std::vector<char>& changed) {
  return run(surfaces, x0, x1, first_particle, &changed);
}

namespace {

// The boxes of primitive i over the motion x0 → x1 (not enlarged).
void set_node_box(BroadphaseInput& in, std::size_t i, const std::vector<Vec3>& x0,
                  const std::vector<Vec3>& x1) {
  in.node_box[i] = swept_box({&x0[in.node_id[i]], &x1[in.node_id[i]]}, 0.0);
}

void set_face_box(BroadphaseInput& in, std::size_t f, const std::vector<Vec3>& x0,
                  const std::vector<Vec3>& x1) {
  const auto& k = in.face_nodes[f];
  in.face_box[f] =
      swept_box({&x0[k[0]], &x0[k[1]], &x0[k[2]], &x1[k[0]], &x1[k[1]], &x1[k[2]]}, 0.0);
}

void set_edge_box(BroadphaseInput& in, std::size_t e, const std::vector<Vec3>& x0,
                  const std::vector<Vec3>& x1) {
  const auto& k = in.edge_nodes[e];
  in.edge_box[e] = swept_box({&x0[k[0]], &x0[k[1]], &x1[k[0]], &x1[k[1]]}, 0.0);
}

}  // namespace

// The pairs to test: the listed pairs whose boxes of the motion overlap (a fresh search's);
// again (`changed`), only the pairs with a side that reads a changed node, with the last
// call's failing pairs.
Candidates StepVerifier::candidate_pairs(const std::vector<Vec3>& x0, const std::vector<Vec3>& x1,
                                         const std::vector<char>* changed) {
  return changed ? changed_pairs(x0, x1, *changed) : step_pairs(x0, x1);
}

// Binding lists, as contact's: the pairs of boxes enlarged by the reach, valid while every
// vertex stays within the reach of where they were built (then a face's or an edge's box now
// lies within its box then, enlarged by the reach). Each call keeps the listed pairs whose
// boxes overlap now: the pairs a fresh search gives.
Candidates StepVerifier::step_pairs(const std::vector<Vec3>& x0, const std::vector<Vec3>& x1) {
  BroadphaseInput& in = input_;
  parallel::for_each(
      in.node_id.size(), [&](std::size_t i) { set_node_box(in, i, x0, x1); },
      parallel::k_light_block);
  parallel::for_each(in.face_nodes.size(), [&](std::size_t f) { set_face_box(in, f, x0, x1); });
  parallel::for_each(in.edge_nodes.size(), [&](std::size_t e) { set_edge_box(in, e, x0, x1); });
  if (!lists_.hold(in.node_id, x0, x1)) {
    BroadphaseInput enlarged = in;
    for (auto* boxes : {&enlarged.node_box, &enlarged.face_box, &enlarged.edge_box})
      for (Box& b : *boxes) b.lo.array() -= lists_.reach(), b.hi.array() += lists_.reach();
    lists_.set(broadphase_->find(enlarged), in.node_id, x0);
  }
  Candidates pairs;
  for (const auto& p : lists_.lists().node_face)
    if (boxes_overlap(in.node_box[p.first], in.face_box[p.second])) pairs.node_face.push_back(p);
  for (const auto& p : lists_.lists().edge_edge)
    if (boxes_overlap(in.edge_box[p.first], in.edge_box[p.second])) pairs.edge_edge.push_back(p);
  return pairs;
}

// A primitive is dirty when a node its pairs' tests read has moved (a face: its tet's nodes; an
// edge: the nodes of the faces at it); the boxes of the dirty ones are set anew, and `reach`
// is the box of them all.
StepVerifier::Dirty StepVerifier::dirty_primitives(const std::vector<Vec3>& x0,
                                                   const std::vector<Vec3>& x1,
                                                   const std::vector<char>& changed) {
  BroadphaseInput& in = input_;
  const auto any = [&](const auto& nodes) {
    for (const Index n : nodes)
      if (changed[n]) return true;
    return false;
  };
  Dirty d;
  d.node.resize(in.node_id.size());
  d.face.resize(in.face_nodes.size());
  d.edge.resize(in.edge_nodes.size());
  for (std::size_t i = 0; i < d.node.size(); ++i) d.node[i] = changed[in.node_id[i]];
  for (std::size_t f = 0; f < d.face.size(); ++f)
    d.face[f] = any(in.face_nodes[f]) || any(mesh_.tets[face_tet_[f]]);
  for (std::size_t e = 0; e < d.edge.size(); ++e) {
    bool dirty = any(in.edge_nodes[e]);
    for (const Index f : edge_faces_[e]) dirty = dirty || (f >= 0 && any(in.face_nodes[f]));
    d.edge[e] = dirty;
  }
  const auto grow = [&](const Box& b) {
    if (!d.any) d.reach = b, d.any = true;
    d.reach.lo = d.reach.lo.cwiseMin(b.lo);
    d.reach.hi = d.reach.hi.cwiseMax(b.hi);
  };
  for (std::size_t i = 0; i < d.node.size(); ++i)
    if (d.node[i]) set_node_box(in, i, x0, x1), grow(in.node_box[i]);
  for (std::size_t f = 0; f < d.face.size(); ++f)
    if (d.face[f]) set_face_box(in, f, x0, x1), grow(in.face_box[f]);
  for (std::size_t e = 0; e < d.edge.size(); ++e)
    if (d.edge[e]) set_edge_box(in, e, x0, x1), grow(in.edge_box[e]);
  return d;
}

// The pairs with a dirty side whose boxes overlap: from the binding lists while the moved nodes
// stay within the reach (x⁰ was checked by the first call of the step), else from a broadphase
// on the dirty primitives and those whose boxes reach theirs.
Candidates StepVerifier::dirty_pairs(const Dirty& d, const std::vector<Vec3>& x1) {
  const BroadphaseInput& in = input_;
  Candidates pairs;
  if (lists_.holds(in.node_id, x1, &d.node)) {
    for (const auto& p : lists_.lists().node_face)
      if ((d.node[p.first] || d.face[p.second]) &&
          boxes_overlap(in.node_box[p.first], in.face_box[p.second]))
        pairs.node_face.push_back(p);
    for (const auto& p : lists_.lists().edge_edge)
      if ((d.edge[p.first] || d.edge[p.second]) &&
          boxes_overlap(in.edge_box[p.first], in.edge_box[p.second]))
        pairs.edge_edge.push_back(p);
    return pairs;
  }
  BroadphaseInput sub;
  std::vector<Index> node_map, face_map, edge_map;
  for (std::size_t i = 0; i < d.node.size(); ++i)
    if (d.node[i] || boxes_overlap(in.node_box[i], d.reach)) {
      node_map.push_back(static_cast<Index>(i));
      sub.node_box.push_back(in.node_box[i]);
      sub.node_id.push_back(in.node_id[i]);
      sub.node_body.push_back(in.node_body[i]);
    }
  for (std::size_t f = 0; f < d.face.size(); ++f)
    if (d.face[f] || boxes_overlap(in.face_box[f], d.reach)) {
      face_map.push_back(static_cast<Index>(f));
      sub.face_box.push_back(in.face_box[f]);
      sub.face_nodes.push_back(in.face_nodes[f]);
      sub.face_body.push_back(in.face_body[f]);
    }
  for (std::size_t e = 0; e < d.edge.size(); ++e)
    if (d.edge[e] || boxes_overlap(in.edge_box[e], d.reach)) {
      edge_map.push_back(static_cast<Index>(e));
      sub.edge_box.push_back(in.edge_box[e]);
      sub.edge_nodes.push_back(in.edge_nodes[e]);
      sub.edge_body.push_back(in.edge_body[e]);
    }
  const Candidates local = broadphase_->find(sub);
  for (const auto& [a, b] : local.node_face)
    if (d.node[node_map[a]] || d.face[face_map[b]])
      pairs.node_face.push_back({node_map[a], face_map[b]});
  for (const auto& [a, b] : local.edge_edge)
    if (d.edge[edge_map[a]] || d.edge[edge_map[b]])
      pairs.edge_edge.push_back(std::minmax(edge_map[a], edge_map[b]));
  return pairs;
}

// Again: only pairs with a dirty side can have changed; the clean pairs that failed last time
// are tested again as they are.
Candidates StepVerifier::changed_pairs(const std::vector<Vec3>& x0, const std::vector<Vec3>& x1,
                                       const std::vector<char>& changed) {
  const Dirty d = dirty_primitives(x0, x1, changed);
  Candidates pairs = d.any ? dirty_pairs(d, x1) : Candidates{};
  for (const auto& p : failed_vf_)
    if (!d.node[p.first] && !d.face[p.second]) pairs.node_face.push_back(p);
  for (const auto& p : failed_ee_)
    if (!d.edge[p.first] && !d.edge[p.second]) pairs.edge_edge.push_back(p);
  std::sort(pairs.node_face.begin(), pairs.node_face.end());
  std::sort(pairs.edge_edge.begin(), pairs.edge_edge.end());
  return pairs;
}

// Each pair's verdict: 0 passes, 1 fails from apart, 2 fails from touching.
std::vector<char> StepVerifier::verdicts(const Candidates& pairs, const std::vector<Vec3>& x0,
                                         const std::vector<Vec3>& x1) const {
  const BroadphaseInput& in = input_;
  // Each pair on the threads: 0 passes, 1 fails from apart, 2 fails from touching. In a
  // distributed run each rank tests its slice of the pairs and the verdicts are gathered in
  // order: every rank holds the same positions, so they are one process's verdicts.
  const std::size_t nvf = pairs.node_face.size();
  std::vector<char> verdict(nvf + pairs.edge_edge.size(), 0);
  mpi::for_each_sliced(verdict, [&](std::size_t k) {
    if (k < nvf) {
      const auto& [ni, fi] = pairs.node_face[k];
      const Index v = in.node_id[ni];
      const auto& f = in.face_nodes[fi];
      const bool touching = exact_vertex_face_ccd(
          {x0[v], x0[f[0]], x0[f[1]], x0[f[2]], x0[v], x0[f[0]], x0[f[1]], x0[f[2]]});
      if (!touching) {
        verdict[k] = exact_vertex_face_ccd(
            {x0[v], x0[f[0]], x0[f[1]], x0[f[2]], x1[v], x1[f[0]], x1[f[1]], x1[f[2]]});
      } else {
        const Tet& t = mesh_.tets[face_tet_[fi]];
        verdict[k] = 2 * exact_point_strictly_in_tet(x1[v], x1[t[0]], x1[t[1]], x1[t[2]], x1[t[3]]);
      }
      return;
    }
    const auto& [ea, eb] = pairs.edge_edge[k - nvf];
    const auto &a = in.edge_nodes[ea], &b = in.edge_nodes[eb];
    const bool touching = exact_edge_edge_ccd(
        {x0[a[0]], x0[a[1]], x0[b[0]], x0[b[1]], x0[a[0]], x0[a[1]], x0[b[0]], x0[b[1]]});
    if (!touching) {
      verdict[k] = exact_edge_edge_ccd(
          {x0[a[0]], x0[a[1]], x0[b[0]], x0[b[1]], x1[a[0]], x1[a[1]], x1[b[0]], x1[b[1]]});
      return;
    }
    // Touching at the start: each edge against the faces at the other, at the end.
    const auto through = [&](const Edge& e, Index other) {
      for (const Index f : edge_faces_[other]) {
        if (f < 0) continue;
        const auto& k = in.face_nodes[f];
        if (exact_segment_crosses_triangle(x1[e[0]], x1[e[1]], x1[k[0]], x1[k[1]], x1[k[2]]))
          return true;
      }
      return false;
    };
    verdict[k] = 2 * (through(a, eb) || through(b, ea));
  });
  return verdict;
}

Verification StepVerifier::run(const std::vector<Surface>& surfaces, const std::vector<Vec3>& x0,
                               const std::vector<Vec3>& x1, Index first_particle,
                               const std::vector<char>* changed) {
  if (stale_ || x0.size() != built_nodes_ || first_particle != built_first_particle_) {
    build(surfaces, first_particle, x0.size());
    stale_ = false;
    built_nodes_ = x0.size();
    built_first_particle_ = first_particle;
    changed = nullptr;  // nothing to reuse
  }
  const Candidates pairs = candidate_pairs(x0, x1, changed);
  Verification r;
  r.pairs_checked = static_cast<long>(pairs.node_face.size() + pairs.edge_edge.size());
  const std::vector<char> verdict = verdicts(pairs, x0, x1);
  // The failing pairs, each with every node its test read (to mark for further passes).
  const BroadphaseInput& in = input_;
  const std::size_t nvf = pairs.node_face.size();
  failed_vf_.clear();
  failed_ee_.clear();
  for (std::size_t k = 0; k < verdict.size(); ++k) {
    if (verdict[k] == 0) continue;
    if (k < nvf)
      failed_vf_.push_back(pairs.node_face[k]);
    else
      failed_ee_.push_back(pairs.edge_edge[k - nvf]);
    FailedPair p;
    p.touching_at_start = verdict[k] == 2;
    const auto add = [&p](Index n) {
      if (std::find(p.nodes.begin(), p.nodes.begin() + p.count, n) == p.nodes.begin() + p.count)
        p.nodes[p.count++] = n;
    };
    if (k < nvf) {
      const auto& [ni, fi] = pairs.node_face[k];
      add(in.node_id[ni]);
      for (const Index n : in.face_nodes[fi]) add(n);
      p.body_a = in.node_body[ni];
      p.body_b = in.face_body[fi];
      if (p.touching_at_start)
        for (const Index n : mesh_.tets[face_tet_[fi]]) add(n);
    } else {
      const auto& [ea, eb] = pairs.edge_edge[k - nvf];
      p.edge_edge = true;
      p.body_a = in.edge_body[ea];
      p.body_b = in.edge_body[eb];
      const auto outward = [&](Index e) {
        Vec3 sum = Vec3::Zero();
        for (const Index f : edge_faces_[e])
          if (f >= 0) sum += face_normal(in.face_nodes[f], x0);
        return sum;
      };
      p.outward_a = outward(ea);
      p.outward_b = outward(eb);
      for (const Index e : {ea, eb}) {
        for (const Index n : in.edge_nodes[e]) add(n);
        if (p.touching_at_start)
          for (const Index f : edge_faces_[e])
            if (f >= 0)
              for (const Index n : in.face_nodes[f]) add(n);
      }
    }
    r.failed.push_back(p);
  }
  return r;
}

}  // namespace tc
