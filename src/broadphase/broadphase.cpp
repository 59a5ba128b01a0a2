#include "tetcontact/broadphase/broadphase.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "tetcontact/parallel/parallel.hpp"

namespace tc {

Box swept_box(std::initializer_list<const Vec3*> points, double margin) {
  Box b;
  b.lo = **points.begin();
  b.hi = b.lo;
  for (const Vec3* p : points) {
    b.lo = b.lo.cwiseMin(*p);
    b.hi = b.hi.cwiseMax(*p);
  }
  b.lo.array() -= margin;
  b.hi.array() += margin;
  return b;
}

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
  std::vector<Index> faces;
  faces.reserve(node_face.size());
  for (const auto& [node, face] : node_face) faces.push_back(face);
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
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

// The contact-boundary notes' spatial index: a virtual uniform grid of cubes (i, j, k), hashed into
// a flat table of buckets; each box is entered in every cube it overlaps with that cube's
// coordinates. A node finds the faces in its cubes; two edges pair in the one cube that holds
// the lower corner of their boxes' intersection (both boxes cover it), so each pair comes
// once. Queries run on the threads; the candidates come out sorted.
class Grid : public Broadphase {
 public:
  explicit Grid(double cell) : cell_(cell) {}
  std::string name() const override { return "grid"; }
  Candidates find(const BroadphaseInput& in) override {
    auto t0 = Clock::now();
    // Cells of twice the mean box size, for the faces and for the edges apart: the boxes of
    // particles (degenerate edges) are far smaller than faces', and a cell sized by the faces
    // put thousands of particles in one cell, all paired with each other.
    const auto cell_size = [this](const std::vector<Box>& boxes) {
      if (cell_ > 0.0) return cell_;
      double sum = 0.0;
      for (const Box& b : boxes) sum += (b.hi - b.lo).maxCoeff();
      const double h = boxes.empty() ? 1.0 : 2.0 * sum / static_cast<double>(boxes.size());
      return h > 0.0 ? h : 1.0;
    };
    const Cells fc{cell_size(in.face_box)}, ec{cell_size(in.edge_box)};
    const Buckets faces = buckets(in.face_box, fc);
    const Buckets edges = buckets(in.edge_box, ec);
    build_seconds = since(t0);
    t0 = Clock::now();
    Candidates c;
    // Node–face: each node's faces sorted and unique, the nodes in order.
    const std::size_t nodes = in.node_box.size();
    std::vector<std::vector<std::pair<Index, Index>>> nf(parallel::block_count(nodes));
    parallel::for_blocks(nodes, [&](std::size_t blk, std::size_t begin, std::size_t end) {
      std::vector<Index> near;
      for (std::size_t un = begin; un < end; ++un) {
        const Index n = static_cast<Index>(un);
        near.clear();
        fc.visit(in.node_box[n], [&](const Cell& cell) {
          const std::size_t bk = cell.hash() & faces.mask;
          for (Index i = faces.begin[bk]; i < faces.begin[bk + 1]; ++i) {
            const Index f = faces.items[i];
            if (boxes_overlap(in.node_box[n], faces.boxes[i]) && admissible_node_face(in, n, f))
              near.push_back(f);
          }
        });
        std::sort(near.begin(), near.end());
        near.erase(std::unique(near.begin(), near.end()), near.end());
        for (const Index f : near) nf[blk].emplace_back(n, f);
      }
    });
    join(nf, c.node_face);
    // Edge–edge: the pairs of each bucket, kept in their reference cube only; sorted after.
    const std::size_t bn = edges.begin.size() - 1;
    std::vector<std::vector<std::pair<Index, Index>>> ee(parallel::block_count(bn));
    parallel::for_blocks(bn, [&](std::size_t blk, std::size_t begin, std::size_t end) {
      for (std::size_t bk = begin; bk < end; ++bk)
        for (Index p = edges.begin[bk]; p < edges.begin[bk + 1]; ++p)
          for (Index q = p + 1; q < edges.begin[bk + 1]; ++q) {
            if (!(edges.cells[p] == edges.cells[q])) continue;  // another cube in the bucket
            const Box &ba = edges.boxes[p], &bb = edges.boxes[q];
            if (!boxes_overlap(ba, bb)) continue;
            const Index a = edges.items[p], b = edges.items[q];
            if (!admissible_edge_edge(in, a, b)) continue;
            if (!(ec.of(ba.lo.cwiseMax(bb.lo)) == edges.cells[p])) continue;  // counted there
            ee[blk].emplace_back(std::min(a, b), std::max(a, b));
          }
    });
    join(ee, c.edge_edge);
    parallel::sort_pairs(c.edge_edge);
    query_seconds = since(t0);
    finish(c);
    return c;
  }

 private:
  struct Cell {
    long i, j, k;
    bool operator==(const Cell& o) const { return i == o.i && j == o.j && k == o.k; }
    // The classic spatial-hash primes, then splitmix64's finaliser, so that the low bits
    // that pick a bucket depend on all of i, j and k.
    std::size_t hash() const {
      std::uint64_t h = static_cast<std::uint64_t>(i * 73856093L ^ j * 19349663L ^ k * 83492791L);
      h ^= h >> 30;
      h *= 0xbf58476d1ce4e5b9ULL;
      h ^= h >> 27;
      h *= 0x94d049bb133111ebULL;
      h ^= h >> 31;
      return static_cast<std::size_t>(h);
    }
  };
  struct Cells {
    double h;
    static long floor_of(double v) {  // std::floor without the call, for finite v
      const long t = static_cast<long>(v);
      return v < static_cast<double>(t) ? t - 1 : t;
    }
    Cell of(const Vec3& p) const {
      return {floor_of(p.x() / h), floor_of(p.y() / h), floor_of(p.z() / h)};
    }
    template <class Visit>
    void visit(const Box& b, Visit&& v) const {
      const Cell lo = of(b.lo), hi = of(b.hi);
      for (long i = lo.i; i <= hi.i; ++i)
        for (long j = lo.j; j <= hi.j; ++j)
          for (long k = lo.k; k <= hi.k; ++k) v(Cell{i, j, k});
    }
  };
  // Boxes by bucket: entry e of bucket b (begin[b] <= e < begin[b + 1]) is box items[e],
  // entered for cube cells[e]; a copy of the box beside it (the tests read them in order).
  struct Buckets {
    std::vector<Index> begin, items;
    std::vector<Cell> cells;
    std::vector<Box> boxes;
    std::size_t mask = 0;
  };
  static Buckets buckets(const std::vector<Box>& boxes, const Cells& grid) {
    std::size_t entries = 0;
    for (const Box& b : boxes) grid.visit(b, [&](const Cell&) { ++entries; });
    Buckets g;
    std::size_t size = 64;
    while (size < 2 * entries) size *= 2;
    g.mask = size - 1;
    g.begin.assign(size + 1, 0);
    for (const Box& b : boxes)
      grid.visit(b, [&](const Cell& c) { ++g.begin[(c.hash() & g.mask) + 1]; });
    for (std::size_t k = 0; k < size; ++k) g.begin[k + 1] += g.begin[k];
    g.items.resize(entries);
    g.cells.resize(entries);
    g.boxes.resize(entries);
    std::vector<Index> next(g.begin.begin(), g.begin.end() - 1);
    for (Index i = 0; i < static_cast<Index>(boxes.size()); ++i)
      grid.visit(boxes[i], [&](const Cell& c) {
        const Index e = next[c.hash() & g.mask]++;
        g.items[e] = i;
        g.cells[e] = c;
        g.boxes[e] = boxes[i];
      });
    return g;
  }
  static void join(const std::vector<std::vector<std::pair<Index, Index>>>& blocks,
                   std::vector<std::pair<Index, Index>>& out) {
    std::size_t n = 0;
    for (const auto& v : blocks) n += v.size();
    out.reserve(n);
    for (const auto& v : blocks) out.insert(out.end(), v.begin(), v.end());
  }
  double cell_;
};

}  // namespace

std::unique_ptr<Broadphase> make_fcl_broadphase(bool tree);  // broadphase_fcl.cpp

std::unique_ptr<Broadphase> make_broadphase(const std::string& name, double cell) {
  if (name == "brute_force") return std::make_unique<BruteForce>();
  if (name == "sweep") return std::make_unique<Sweep>();
  if (name == "grid") return std::make_unique<Grid>(cell);
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
