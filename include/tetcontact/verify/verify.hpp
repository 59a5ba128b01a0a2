// The verify stage: the step's motion verified free of intersection, with the exact CCD, on the
// detection's one broadphase update (its primitives and binding lists, ContactCandidates).
//
// Forbidden during a step, every point moving linearly from xⁿ to xⁿ⁺¹ (as committed, in
// doubles), for primitives of different bodies (a particle is a vertex of no body):
//   - a vertex and a face, or two edges, that are apart at the start and meet at some time of
//     the step (exact CCD, touching included: reaching a touch from apart is flagged too, so
//     the test errs on the safe side);
//   - a vertex that touches a face at the start and ends strictly inside the face's tet, or
//     two edges that touch at the start and end with one strictly through a face at the
//     other (one of the two surface faces at that edge): touching, and staying in touch, is
//     allowed; going on through is not.
// Degenerate cases: a degenerate face or edge is decided by the exact CCD as it is (coplanar
// motions, zero-length edges); "strictly" means every orientation non-zero, so a vertex
// ending on a face or an edge ending in a face's plane is touching. What is not caught: a
// pair touching at the start that passes through the other body and out again within the
// one step (it would have to move farther than a cell in a step, which the stable step rules
// out for the speeds of the cases).
#pragma once

#include <array>
#include <utility>
#include <vector>

#include "tetcontact/broadphase/contact_candidates.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

/// A pair that failed, with every node its test read: vertex–face (v, f0, f1, f2, and the
/// apex of the face's tet when they touched at the start) or edge–edge (a0, a1, b0, b1, and
/// the third nodes of the faces at each edge when they touched). The pair itself is
/// nodes[0..3]: the vertex and the face's nodes in the surface's outward order, or edge A
/// (nodes[0], nodes[1]) and edge B (nodes[2], nodes[3]).
struct FailedPair {
  std::array<Index, 8> nodes{};
  int count = 0;
  bool edge_edge = false;
  bool touching_at_start = false;
  Index body_a = -1, body_b = -1;  // the vertex's (−1: a particle) or edge A's; the face's or B's
  Vec3 outward_a = Vec3::Zero(), outward_b = Vec3::Zero();  // edges: Σ outward normals at xⁿ
};

struct Verification {
  long pairs_checked = 0;  // vertex–face and edge–edge pairs whose swept boxes overlap
  long searches = 0;       // broadphase searches the lists needed for the end positions
  std::vector<FailedPair> failed;
};

/// The pairs: the detection's lists (ContactCandidates with `verify`, which lists the surface
/// edges and keeps the reach), kept while the end positions stay within its reach, else
/// found anew for xⁿ → x1; of them, those whose boxes of xⁿ → x1 overlap. The primitives are
/// the candidates' (the surface nodes, then the particles as vertices of no body; the faces;
/// the edges). Within a step the near pairs (boxes within k_slack of the reach of overlapping)
/// stand in for the lists while the moved vertices stay within that slack.
class StepVerifier {
 public:
  /// The slack of the near pairs within a step, over the lists' reach.
  static constexpr double k_slack = 0.1;
  /// `mesh` gives the face tets' nodes.
  explicit StepVerifier(const Mesh& mesh) : mesh_(mesh) {}
  /// Verifies the motion st.x → x1 of the surfaces' nodes and of the particles.
  Verification verify(const State& st, const std::vector<Vec3>& x1, ContactCandidates& candidates);
  /// The same after a change of x1 at the nodes `changed` (node ids), st.x and the surfaces as
  /// at the last call: only the pairs whose tests read a changed node (the near pairs of the
  /// primitives at those nodes) are tested again, with the last call's failing pairs; the others
  /// passed and still do.
  Verification verify_again(const State& st, const std::vector<Vec3>& x1,
                            ContactCandidates& candidates, const std::vector<Index>& changed);
  /// The surfaces changed (fracture): the maps over the primitives are rebuilt at the next call.
  void surfaces_changed() { stale_ = true; }

 private:
  using Pair = std::pair<Index, Index>;
  // The pairs to test: indices into the near pairs, ascending.
  struct Tests {
    std::vector<Index> vf, ee;
  };
  // Compressed rows: the items of row r are items[begin[r] .. begin[r + 1]).
  struct Rows {
    std::vector<Index> begin, items;
  };
  void build(const ContactCandidates& candidates, const State& st);
  void list_pairs(const ContactCandidates& candidates);
  void set_boxes(const State& st, const std::vector<Vec3>& x1);
  Index node_of(Index i) const;  // the node id of vertex primitive i
  void mark_dirty(const State& st, const std::vector<Vec3>& x1, const std::vector<Index>& changed);
  Tests near_pairs(const std::vector<Vec3>& x1);
  Tests dirty_pairs();
  Verification run(const State& st, const std::vector<Vec3>& x1, const Tests& tests);
  std::vector<char> verdicts(const Tests& tests, const std::vector<Vec3>& x0,
                             const std::vector<Vec3>& x1);

  const Mesh& mesh_;
  const SurfacePrimitives* prims_ = nullptr;
  bool stale_ = true;
  Index vertices_ = 0, first_particle_ = 0;  // the surface nodes and particles; node id base
  // Boxes of xⁿ → x1 of each vertex (surface nodes, then particles), face and edge.
  std::vector<Box> node_box_, face_box_, edge_box_;
  // From a node id to the primitives whose tests read it: its vertex; the faces of the tets
  // holding it; the edges at it or at a face of theirs that holds it.
  const std::vector<Index>* vertex_of_ = nullptr;  // the candidates' node_slots()
  Rows faces_at_, edges_at_;
  // The listed pairs in this numbering (vertex, face) and (edge, edge), for the candidates'
  // lists of `listed_version_`.
  std::vector<Pair> vf_, ee_;
  long listed_version_ = -1;
  // Within a step: the listed pairs whose boxes, each enlarged by the slack, overlap (sorted),
  // with the vertices' end positions they were found at (`anchor_`). While every vertex's end
  // position stays within the slack of its anchor (per axis), a listed pair whose boxes
  // overlap is near.
  std::vector<Pair> near_vf_, near_ee_;
  std::vector<Vec3> anchor_;
  // Each near pair at xⁿ: 0 not yet tested, 1 apart, 2 touching.
  std::vector<char> start_vf_, start_ee_;
  double slack_ = 0.0;
  // The primitives a verify_again found dirty (flags, and their indices).
  std::vector<char> dirty_vertex_, dirty_face_, dirty_edge_;
  std::vector<Index> dirty_vertices_, dirty_faces_, dirty_edges_;
  // The last call's failing pairs, sorted.
  std::vector<Pair> failed_vf_, failed_ee_;
};

}  // namespace tc
