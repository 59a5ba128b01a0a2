#include "tetcontact/broadphase/broadphase.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "tetcontact/parallel/parallel.hpp"

namespace tc {

bool admissible_node_face(const BroadphaseInput& in, Index node, Index face) {
  if (in.node_body[node] != in.face_body[face]) return true;
  if (!in.self_pairs) return false;
  const auto& f = in.face_nodes[face];
  const Index v = in.node_id[node];
  return f[0] != v && f[1] != v && f[2] != v;
}

bool admissible_edge_edge(const BroadphaseInput& in, Index a, Index b) {
  if (in.edge_body[a] != in.edge_body[b]) return true;
  if (!in.self_pairs) return false;
  const auto& ea = in.edge_nodes[a];
  const auto& eb = in.edge_nodes[b];
  return ea[0] != eb[0] && ea[0] != eb[1] && ea[1] != eb[0] && ea[1] != eb[1];
}

std::vector<Index> listed_faces(const std::vector<std::pair<Index, Index>>& node_face) {
  // Marked, then read in order: no sort of the (many) pairs' faces.
  Index top = -1;
  for (const auto& p : node_face) top = std::max(top, p.second);
  std::vector<char> listed(static_cast<std::size_t>(top + 1), 0);
  for (const auto& p : node_face) listed[p.second] = 1;
  std::vector<Index> faces;
  for (Index f = 0; f <= top; ++f)
    if (listed[f]) faces.push_back(f);
  return faces;
}

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void finish(Candidates& c) {
  if (!std::is_sorted(c.node_face.begin(), c.node_face.end()))  // the grid's come sorted
    std::sort(c.node_face.begin(), c.node_face.end());
  c.node_face.erase(std::unique(c.node_face.begin(), c.node_face.end()), c.node_face.end());
  for (auto& p : c.edge_edge)
    if (p.first > p.second) std::swap(p.first, p.second);
  std::sort(c.edge_edge.begin(), c.edge_edge.end());
  c.edge_edge.erase(std::unique(c.edge_edge.begin(), c.edge_edge.end()), c.edge_edge.end());
}

// The oracle: every pair tested.
class BruteForce : public Broadphase {
 public:
  std::string name() const override { return "brute_force"; }
  Candidates find(const BroadphaseInput& in) override {
    const auto t0 = Clock::now();
    Candidates c;
    for (Index n = 0; n < static_cast<Index>(in.node_box.size()); ++n)
      for (Index f = 0; f < static_cast<Index>(in.face_box.size()); ++f)
        if (admissible_node_face(in, n, f) && boxes_overlap(in.node_box[n], in.face_box[f]))
          c.node_face.emplace_back(n, f);
    for (Index a = 0; a < static_cast<Index>(in.edge_box.size()); ++a)
      for (Index b = a + 1; b < static_cast<Index>(in.edge_box.size()); ++b)
        if (admissible_edge_edge(in, a, b) && boxes_overlap(in.edge_box[a], in.edge_box[b]))
          c.edge_edge.emplace_back(a, b);
    build_seconds = 0.0;
    query_seconds = since(t0);
    return c;
  }
};

// Plain sort-and-sweep along x: sort both sets by lo.x, sweep, test the other axes exactly.
class Sweep : public Broadphase {
 public:
  std::string name() const override { return "sweep"; }
  Candidates find(const BroadphaseInput& in) override {
    auto t0 = Clock::now();
    const auto order = [](const std::vector<Box>& boxes) {
      std::vector<Index> idx(boxes.size());
      for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<Index>(i);
      std::sort(idx.begin(), idx.end(), [&](Index a, Index b) {
        return boxes[a].lo.x() < boxes[b].lo.x() || (boxes[a].lo.x() == boxes[b].lo.x() && a < b);
      });
      return idx;
    };
    const auto nodes = order(in.node_box), faces = order(in.face_box), edges = order(in.edge_box);
    build_seconds = since(t0);
    t0 = Clock::now();
    Candidates c;
    // Node-face: merge-style sweep over both sorted lists.
    sweep_two(nodes, in.node_box, faces, in.face_box, [&](Index n, Index f) {
      if (admissible_node_face(in, n, f)) c.node_face.emplace_back(n, f);
    });
    // Edge-edge: one list against itself.
    for (std::size_t p = 0; p < edges.size(); ++p) {
      const Box& a = in.edge_box[edges[p]];
      for (std::size_t q = p + 1; q < edges.size(); ++q) {
        const Box& b = in.edge_box[edges[q]];
        if (b.lo.x() > a.hi.x()) break;
        if (boxes_overlap(a, b) && admissible_edge_edge(in, edges[p], edges[q]))
          c.edge_edge.emplace_back(edges[p], edges[q]);
      }
    }
    query_seconds = since(t0);
    finish(c);
    return c;
  }

 private:
  // All overlapping (a, b) between two x-sorted lists: a pair is found from whichever box
  // starts first (or from a when both start at the same x).
  template <class Emit>
  static void sweep_two(const std::vector<Index>& ai, const std::vector<Box>& a,
                        const std::vector<Index>& bi, const std::vector<Box>& b, Emit&& emit) {
    std::size_t p = 0, q = 0;
    while (p < ai.size() && q < bi.size()) {
      if (a[ai[p]].lo.x() <= b[bi[q]].lo.x()) {
        const Box& box = a[ai[p]];
        for (std::size_t k = q; k < bi.size() && b[bi[k]].lo.x() <= box.hi.x(); ++k)
          if (boxes_overlap(box, b[bi[k]])) emit(ai[p], bi[k]);
        ++p;
      } else {
        const Box& box = b[bi[q]];
        for (std::size_t k = p; k < ai.size() && a[ai[k]].lo.x() <= box.hi.x(); ++k)
          if (boxes_overlap(a[ai[k]], box)) emit(ai[k], bi[q]);
        ++q;
      }
    }
  }
};

}  // namespace

std::unique_ptr<Broadphase> make_fcl_broadphase(bool tree);     // broadphase_fcl.cpp
std::unique_ptr<Broadphase> make_grid_broadphase(double cell);  // grid.cpp

std::unique_ptr<Broadphase> make_broadphase(const std::string& name, double cell) {
  if (name == "brute_force") return std::make_unique<BruteForce>();
  if (name == "sweep") return std::make_unique<Sweep>();
  if (name == "grid") return make_grid_broadphase(cell);
  if (name == "fcl_tree") return make_fcl_broadphase(true);
  if (name == "fcl_sap") return make_fcl_broadphase(false);
  throw std::invalid_argument("unknown broadphase '" + name + "'");
}

const std::vector<std::string>& broadphase_names() {
  static const std::vector<std::string> names{"fcl_tree", "fcl_sap", "grid", "sweep",
                                              "brute_force"};
  return names;
}

}  // namespace tc
