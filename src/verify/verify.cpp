#include "tetcontact/verify/verify.hpp"

#include <algorithm>
#include <stdexcept>

#include "tetcontact/diagnostics/penetration.hpp"
#include "tetcontact/narrowphase/exact_ccd.hpp"
#include "tetcontact/parallel/mpi.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {

namespace {

// Rows of `rows` items from (row, item) entries, each row's items in the order given.
template <class Entries>
void fill_rows(std::size_t rows, const Entries& entries, std::vector<Index>& begin,
               std::vector<Index>& items) {
  begin.assign(rows + 1, 0);
  entries([&](Index row, Index) { ++begin[static_cast<std::size_t>(row) + 1]; });
  for (std::size_t r = 0; r < rows; ++r) begin[r + 1] += begin[r];
  items.resize(static_cast<std::size_t>(begin[rows]));
  std::vector<Index> at(begin.begin(), begin.end() - 1);
  entries([&](Index row, Index item) { items[static_cast<std::size_t>(at[row]++)] = item; });
}

}  // namespace

Index StepVerifier::node_of(Index i) const {
  const Index surface = static_cast<Index>(prims_->nodes.size());
  return i < surface ? prims_->nodes[i] : first_particle_ + (i - surface);
}

// The maps from nodes to the primitives whose tests read them: a face's test reads its tet's
// nodes (the apex when touching at the start), an edge's the nodes of the two faces at it.
void StepVerifier::build(const ContactCandidates& candidates, const State& st) {
  prims_ = &candidates.primitives();
  const SurfacePrimitives& p = *prims_;
  const Index surface = static_cast<Index>(p.nodes.size());
  first_particle_ = st.first_particle;
  vertices_ = surface + st.particle_count();
  const std::size_t mesh_nodes = static_cast<std::size_t>(st.first_particle);
  vertex_of_ = &candidates.node_slots();
  fill_rows(
      mesh_nodes,
      [&](auto&& add) {
        for (std::size_t f = 0; f < p.faces.size(); ++f)
          for (const Index n : mesh_.tets[p.face_tet[f]]) add(n, static_cast<Index>(f));
      },
      faces_at_.begin, faces_at_.items);
  fill_rows(
      mesh_nodes,
      [&](auto&& add) {
        for (std::size_t e = 0; e < p.edges.size(); ++e) {
          std::array<Index, 8> seen{};
          int count = 0;
          const auto once = [&](Index n) {
            if (std::find(seen.begin(), seen.begin() + count, n) != seen.begin() + count) return;
            seen[count++] = n;
            add(n, static_cast<Index>(e));
          };
          for (const Index n : p.edges[e]) once(n);
          for (const Index f : p.edge_faces[e])
            if (f >= 0)
              for (const Index n : p.faces[f]) once(n);
        }
      },
      edges_at_.begin, edges_at_.items);
  dirty_vertex_.assign(static_cast<std::size_t>(vertices_), 0);
  dirty_face_.assign(p.faces.size(), 0);
  dirty_edge_.assign(p.edges.size(), 0);
  failed_vf_.clear();
  failed_ee_.clear();
  listed_version_ = -1;
  slack_ = k_slack * candidates.reach();
  stale_ = false;
}

// The candidates' pairs in this numbering: the bodies' (surface node, face), the particles'
// (particle, face) as (surface nodes + particle, face), both sorted, so the whole is sorted.
void StepVerifier::list_pairs(const ContactCandidates& candidates) {
  if (candidates.version() == listed_version_) return;
  listed_version_ = candidates.version();
  const Index surface = static_cast<Index>(prims_->nodes.size());
  vf_ = candidates.bodies().node_face;
  if (candidates.settings().particles)
    for (const auto& [i, f] : candidates.particles().node_face) vf_.emplace_back(surface + i, f);
  ee_ = candidates.bodies().edge_edge;
}

void StepVerifier::set_boxes(const State& st, const std::vector<Vec3>& x1) {
  const std::vector<Vec3>& x0 = st.x;
  const SurfacePrimitives& p = *prims_;
  node_box_.resize(static_cast<std::size_t>(vertices_));
  face_box_.resize(p.faces.size());
  edge_box_.resize(p.edges.size());
  parallel::for_each(
      node_box_.size(),
      [&](std::size_t i) {
        const Index n = node_of(static_cast<Index>(i));
        node_box_[i] = swept_box({&x0[n], &x1[n]}, 0.0);
      },
      parallel::k_light_block);
  parallel::for_each(face_box_.size(), [&](std::size_t f) {
    const Face& k = p.faces[f];
    face_box_[f] =
        swept_box({&x0[k[0]], &x0[k[1]], &x0[k[2]], &x1[k[0]], &x1[k[1]], &x1[k[2]]}, 0.0);
  });
  parallel::for_each(edge_box_.size(), [&](std::size_t e) {
    const Edge& k = p.edges[e];
    edge_box_[e] = swept_box({&x0[k[0]], &x0[k[1]], &x1[k[0]], &x1[k[1]]}, 0.0);
  });
}

Verification StepVerifier::verify(const State& st, const std::vector<Vec3>& x1,
                                  ContactCandidates& candidates) {
  if (stale_ || prims_ != &candidates.primitives() ||
      vertices_ != static_cast<Index>(candidates.primitives().nodes.size()) + st.particle_count())
    build(candidates, st);
  const long searches = candidates.lists_for(st, x1) ? 1 : 0;
  list_pairs(candidates);
  set_boxes(st, x1);
  Verification r = run(st, x1, near_pairs(x1));
  r.searches = searches;
  return r;
}

namespace {

// Whether boxes a and b, each enlarged by s, overlap (with a quarter of s more for rounding).
bool near(const Box& a, const Box& b, double s) {
  const double d = 2.5 * s;
  return a.lo.x() <= b.hi.x() + d && b.lo.x() <= a.hi.x() + d && a.lo.y() <= b.hi.y() + d &&
         b.lo.y() <= a.hi.y() + d && a.lo.z() <= b.hi.z() + d && b.lo.z() <= a.hi.z() + d;
}

}  // namespace

// One pass over the listed pairs: the near ones, with the vertices' end positions as their
// anchors and no verdict at the start known yet; those whose boxes overlap are returned.
StepVerifier::Tests StepVerifier::near_pairs(const std::vector<Vec3>& x1) {
  Tests tests;
  near_vf_.clear();
  near_ee_.clear();
  for (const Pair& p : vf_) {
    const Box &a = node_box_[p.first], &b = face_box_[p.second];
    if (!near(a, b, slack_)) continue;
    if (boxes_overlap(a, b)) tests.vf.push_back(static_cast<Index>(near_vf_.size()));
    near_vf_.push_back(p);
  }
  for (const Pair& p : ee_) {
    const Box &a = edge_box_[p.first], &b = edge_box_[p.second];
    if (!near(a, b, slack_)) continue;
    if (boxes_overlap(a, b)) tests.ee.push_back(static_cast<Index>(near_ee_.size()));
    near_ee_.push_back(p);
  }
  start_vf_.assign(near_vf_.size(), 0);
  start_ee_.assign(near_ee_.size(), 0);
  anchor_.resize(static_cast<std::size_t>(vertices_));
  for (Index i = 0; i < vertices_; ++i) anchor_[i] = x1[node_of(i)];
  return tests;
}

// The primitives whose tests read a changed node, their boxes set anew.
void StepVerifier::mark_dirty(const State& st, const std::vector<Vec3>& x1,
                              const std::vector<Index>& changed) {
  const std::vector<Vec3>& x0 = st.x;
  const SurfacePrimitives& p = *prims_;
  const Index surface = static_cast<Index>(p.nodes.size());
  dirty_vertices_.clear();
  dirty_faces_.clear();
  dirty_edges_.clear();
  const auto mark = [](std::vector<char>& flags, std::vector<Index>& list, Index i) {
    if (flags[i]) return;
    flags[i] = 1;
    list.push_back(i);
  };
  for (const Index n : changed) {
    if (n >= first_particle_) {
      mark(dirty_vertex_, dirty_vertices_, surface + (n - first_particle_));
      continue;
    }
    if ((*vertex_of_)[n] >= 0) mark(dirty_vertex_, dirty_vertices_, (*vertex_of_)[n]);
    for (Index k = faces_at_.begin[n]; k < faces_at_.begin[n + 1]; ++k)
      mark(dirty_face_, dirty_faces_, faces_at_.items[k]);
    for (Index k = edges_at_.begin[n]; k < edges_at_.begin[n + 1]; ++k)
      mark(dirty_edge_, dirty_edges_, edges_at_.items[k]);
  }
  for (const Index i : dirty_vertices_) {
    const Index n = node_of(i);
    node_box_[i] = swept_box({&x0[n], &x1[n]}, 0.0);
  }
  for (const Index f : dirty_faces_) {
    const Face& k = p.faces[f];
    face_box_[f] =
        swept_box({&x0[k[0]], &x0[k[1]], &x0[k[2]], &x1[k[0]], &x1[k[1]], &x1[k[2]]}, 0.0);
  }
  for (const Index e : dirty_edges_) {
    const Edge& k = p.edges[e];
    edge_box_[e] = swept_box({&x0[k[0]], &x0[k[1]], &x1[k[0]], &x1[k[1]]}, 0.0);
  }
}

// The near pairs with a dirty side whose boxes overlap, in the lists' order (sorted).
StepVerifier::Tests StepVerifier::dirty_pairs() {
  Tests tests;
  for (std::size_t k = 0; k < near_vf_.size(); ++k) {
    const Pair& p = near_vf_[k];
    if ((dirty_vertex_[p.first] || dirty_face_[p.second]) &&
        boxes_overlap(node_box_[p.first], face_box_[p.second]))
      tests.vf.push_back(static_cast<Index>(k));
  }
  for (std::size_t k = 0; k < near_ee_.size(); ++k) {
    const Pair& p = near_ee_[k];
    if ((dirty_edge_[p.first] || dirty_edge_[p.second]) &&
        boxes_overlap(edge_box_[p.first], edge_box_[p.second]))
      tests.ee.push_back(static_cast<Index>(k));
  }
  return tests;
}

// Again: only pairs with a dirty side can have changed; the clean pairs that failed last time
// are tested again as they are.
Verification StepVerifier::verify_again(const State& st, const std::vector<Vec3>& x1,
                                        ContactCandidates& candidates,
                                        const std::vector<Index>& changed) {
  if (stale_ || prims_ != &candidates.primitives()) return verify(st, x1, candidates);
  const long searches = candidates.lists_for(st, x1, &changed) ? 1 : 0;
  const bool listed_anew = candidates.version() != listed_version_;
  list_pairs(candidates);
  mark_dirty(st, x1, changed);
  // The near pairs still hold while every moved vertex is within the slack of its anchor; else
  // they are found anew from the lists (every box is current).
  bool hold = !listed_anew;
  for (const Index i : dirty_vertices_)
    hold = hold && ((x1[node_of(i)] - anchor_[i]).cwiseAbs().array() <= slack_).all();
  if (!hold) near_pairs(x1);
  // Both parts sorted: merged in order. A clean failing pair's boxes are as when it was tested,
  // overlapping: it is near.
  const Tests dirty = dirty_pairs();
  Tests tests;
  const auto merge_clean = [](const std::vector<Index>& found, const std::vector<Pair>& failed,
                              const std::vector<Pair>& near, const auto& clean,
                              std::vector<Index>& out) {
    std::vector<Index> kept;
    for (const Pair& p : failed) {
      if (!clean(p)) continue;
      const auto at = std::lower_bound(near.begin(), near.end(), p);
      if (at == near.end() || *at != p)
        throw std::logic_error("StepVerifier: a failing pair is not among the near pairs");
      kept.push_back(static_cast<Index>(at - near.begin()));
    }
    out.resize(found.size() + kept.size());
    std::merge(found.begin(), found.end(), kept.begin(), kept.end(), out.begin());
  };
  merge_clean(
      dirty.vf, failed_vf_, near_vf_,
      [&](const Pair& p) { return !dirty_vertex_[p.first] && !dirty_face_[p.second]; }, tests.vf);
  merge_clean(
      dirty.ee, failed_ee_, near_ee_,
      [&](const Pair& p) { return !dirty_edge_[p.first] && !dirty_edge_[p.second]; }, tests.ee);
  for (const Index i : dirty_vertices_) dirty_vertex_[i] = 0;
  for (const Index f : dirty_faces_) dirty_face_[f] = 0;
  for (const Index e : dirty_edges_) dirty_edge_[e] = 0;
  Verification r = run(st, x1, tests);
  r.searches = searches;
  return r;
}

// Each pair's verdict: 0 passes, 1 fails from apart, 2 fails from touching. Whether a pair
// touches at the start depends on xⁿ alone: found once a step per near pair (1 + touching).
std::vector<char> StepVerifier::verdicts(const Tests& tests, const std::vector<Vec3>& x0,
                                         const std::vector<Vec3>& x1) {
  const SurfacePrimitives& in = *prims_;
  // Each pair on the threads. In a distributed run each rank tests its slice of the pairs and
  // the verdicts are gathered in order: every rank holds the same positions, so they are one
  // process's verdicts (each rank knows the start of its own slice's pairs only).
  const std::size_t nvf = tests.vf.size();
  std::vector<char> verdict(nvf + tests.ee.size(), 0);
  mpi::for_each_sliced(verdict, [&](std::size_t k) {
    if (k < nvf) {
      const Index t = tests.vf[k];
      const auto& [ni, fi] = near_vf_[t];
      const Index v = node_of(ni);
      const auto& f = in.faces[fi];
      if (start_vf_[t] == 0)
        start_vf_[t] = 1 + exact_vertex_face_ccd({x0[v], x0[f[0]], x0[f[1]], x0[f[2]], x0[v],
                                                  x0[f[0]], x0[f[1]], x0[f[2]]});
      const bool touching = start_vf_[t] == 2;
      if (!touching) {
        verdict[k] = exact_vertex_face_ccd(
            {x0[v], x0[f[0]], x0[f[1]], x0[f[2]], x1[v], x1[f[0]], x1[f[1]], x1[f[2]]});
      } else {
        const Tet& t = mesh_.tets[in.face_tet[fi]];
        verdict[k] = 2 * exact_point_strictly_in_tet(x1[v], x1[t[0]], x1[t[1]], x1[t[2]], x1[t[3]]);
      }
      return;
    }
    const Index t = tests.ee[k - nvf];
    const auto& [ea, eb] = near_ee_[t];
    const auto &a = in.edges[ea], &b = in.edges[eb];
    if (start_ee_[t] == 0)
      start_ee_[t] = 1 + exact_edge_edge_ccd({x0[a[0]], x0[a[1]], x0[b[0]], x0[b[1]], x0[a[0]],
                                              x0[a[1]], x0[b[0]], x0[b[1]]});
    const bool touching = start_ee_[t] == 2;
    if (!touching) {
      verdict[k] = exact_edge_edge_ccd(
          {x0[a[0]], x0[a[1]], x0[b[0]], x0[b[1]], x1[a[0]], x1[a[1]], x1[b[0]], x1[b[1]]});
      return;
    }
    // Touching at the start: each edge against the faces at the other, at the end.
    const auto through = [&](const Edge& e, Index other) {
      for (const Index f : in.edge_faces[other]) {
        if (f < 0) continue;
        const auto& k = in.faces[f];
        if (exact_segment_crosses_triangle(x1[e[0]], x1[e[1]], x1[k[0]], x1[k[1]], x1[k[2]]))
          return true;
      }
      return false;
    };
    verdict[k] = 2 * (through(a, eb) || through(b, ea));
  });
  return verdict;
}

Verification StepVerifier::run(const State& st, const std::vector<Vec3>& x1, const Tests& tests) {
  const std::vector<Vec3>& x0 = st.x;
  Verification r;
  r.pairs_checked = static_cast<long>(tests.vf.size() + tests.ee.size());
  const std::vector<char> verdict = verdicts(tests, x0, x1);
  // The failing pairs, each with every node its test read (to mark for further passes).
  const SurfacePrimitives& in = *prims_;
  const Index surface = static_cast<Index>(in.nodes.size());
  const std::size_t nvf = tests.vf.size();
  failed_vf_.clear();
  failed_ee_.clear();
  for (std::size_t k = 0; k < verdict.size(); ++k) {
    if (verdict[k] == 0) continue;
    if (k < nvf)
      failed_vf_.push_back(near_vf_[tests.vf[k]]);
    else
      failed_ee_.push_back(near_ee_[tests.ee[k - nvf]]);
    FailedPair p;
    p.touching_at_start = verdict[k] == 2;
    const auto add = [&p](Index n) {
      if (std::find(p.nodes.begin(), p.nodes.begin() + p.count, n) == p.nodes.begin() + p.count)
        p.nodes[p.count++] = n;
    };
    if (k < nvf) {
      const auto& [ni, fi] = near_vf_[tests.vf[k]];
      add(node_of(ni));
      for (const Index n : in.faces[fi]) add(n);
      p.body_a = ni < surface ? in.node_body[ni] : -1;
      p.body_b = in.face_body[fi];
      if (p.touching_at_start)
        for (const Index n : mesh_.tets[in.face_tet[fi]]) add(n);
    } else {
      const auto& [ea, eb] = near_ee_[tests.ee[k - nvf]];
      p.edge_edge = true;
      p.body_a = in.edge_body[ea];
      p.body_b = in.edge_body[eb];
      const auto outward = [&](Index e) {
        Vec3 sum = Vec3::Zero();
        for (const Index f : in.edge_faces[e])
          if (f >= 0) sum += face_normal(in.faces[f], x0);
        return sum;
      };
      p.outward_a = outward(ea);
      p.outward_b = outward(eb);
      for (const Index e : {ea, eb}) {
        for (const Index n : in.edges[e]) add(n);
        if (p.touching_at_start)
          for (const Index f : in.edge_faces[e])
            if (f >= 0)
              for (const Index n : in.faces[f]) add(n);
      }
    }
    r.failed.push_back(p);
  }
  return r;
}

}  // namespace tc
