// Broadphase: candidate pairs of surface primitives whose swept, inflated boxes overlap.
//
// Plain data in (boxes, owning bodies, vertex ids), plain data out (sorted index pairs).
// Every method returns exactly the pairs a brute-force test of closed boxes returns
// (touching counts): the FCL managers are given boxes enlarged outward by a few ulps and their
// answers are filtered by the exact test, so neither FCL's rounding nor its sweep-and-prune's
// strict comparisons can lose a pair (../shared/ANCHORS.md). FCL stays in one .cpp.
#pragma once

#include <array>
#include <initializer_list>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

struct Box {
  Vec3 lo = Vec3::Zero();
  Vec3 hi = Vec3::Zero();
};

/// Closed boxes overlap (touching counts).
inline bool boxes_overlap(const Box& a, const Box& b) {
  return a.lo.x() <= b.hi.x() && b.lo.x() <= a.hi.x() && a.lo.y() <= b.hi.y() &&
         b.lo.y() <= a.hi.y() && a.lo.z() <= b.hi.z() && b.lo.z() <= a.hi.z();
}

/// The box of points p (at both ends of the step), inflated by `margin`. Inline: the stages box
/// every surface primitive every step.
inline Box swept_box(std::initializer_list<const Vec3*> points, double margin) {
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

struct BroadphaseInput {
  // Vertices (node primitives), faces and edges, each with a box and an owning body.
  std::vector<Box> node_box, face_box, edge_box;
  std::vector<Index> node_id;  // vertex id of each node primitive
  std::vector<std::array<Index, 3>> face_nodes;
  std::vector<std::array<Index, 2>> edge_nodes;
  std::vector<Index> node_body, face_body, edge_body;
  /// Pairs within one body are kept too (pairs sharing a vertex are always skipped); off for
  /// contact between bodies.
  bool self_pairs = false;
};

/// Sorted (node primitive, face) and (edge, edge with a larger index) pairs.
struct Candidates {
  std::vector<std::pair<Index, Index>> node_face;
  std::vector<std::pair<Index, Index>> edge_edge;
};

/// The faces that (node, face) pairs name, sorted, each once.
std::vector<Index> listed_faces(const std::vector<std::pair<Index, Index>>& node_face);

/// Whether a pair of primitives is admissible (different bodies, or self pairs without a
/// shared vertex).
bool admissible_node_face(const BroadphaseInput& in, Index node, Index face);
bool admissible_edge_edge(const BroadphaseInput& in, Index a, Index b);

class Broadphase {
 public:
  virtual ~Broadphase() = default;
  virtual std::string name() const = 0;
  /// Candidate pairs for this input.
  virtual Candidates find(const BroadphaseInput& in) = 0;
  /// Seconds of the last call spent building/updating the structure and querying it.
  double build_seconds = 0.0, query_seconds = 0.0;
  /// Keep the memory of what a call builds for the next (the grid's cubes and lists: no
  /// allocation once warm; freed and allocated again each call, glibc keeps the freed pages, and
  /// Hertz's run held 470 bytes a tet against 339 kept); off, the grid frees it after each call.
  /// FCL's managers are kept either way (they are updated, not rebuilt).
  bool keep_memory = true;
};

/// The methods: "brute_force" (the oracle), "sweep" (plain sort-and-sweep on x), "grid"
/// (the contact-boundary notes' hashed uniform grid, cube size `cell` or, when 0, twice the mean
/// box size), "fcl_tree" (FCL's dynamic AABB tree, the default), "fcl_sap" (FCL's sweep-and-prune).
/// Throws std::invalid_argument for another name.
std::unique_ptr<Broadphase> make_broadphase(const std::string& name, double cell = 0.0);

const std::vector<std::string>& broadphase_names();

/// The grid's lanes: 8 boxes a test where the processor has AVX2, 4 (SSE2) on any x86-64, or 1.
/// Sets them (n ≤ 0 or above the processor's: its best) and returns those in use. The answers
/// are the same for every width (the tests compare them); the switch is for those tests.
int set_grid_lanes(int n);

}  // namespace tc
