// The step's motion verified free of intersection, with the exact CCD.
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
#include <memory>
#include <vector>

#include "tetcontact/broadphase/binding_lists.hpp"
#include "tetcontact/broadphase/broadphase.hpp"
#include "tetcontact/mesh/surface.hpp"

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
  std::vector<FailedPair> failed;
};

class StepVerifier {
 public:
  /// `mesh` gives the face tets' nodes; the surfaces are read at each call (fracture changes
  /// them).
  explicit StepVerifier(const Mesh& mesh);
  /// Verifies the motion x0 → x1 of the surfaces' nodes and of the particles (nodes from
  /// `first_particle` on).
  Verification verify(const std::vector<Surface>& surfaces, const std::vector<Vec3>& x0,
                      const std::vector<Vec3>& x1, Index first_particle);
  /// The surfaces changed (fracture): the primitives are rebuilt at the next call.
  void surfaces_changed() { stale_ = true; }
  /// The same after a change of x1 at the nodes marked in `changed` (one entry per node), the
  /// surfaces and x0 as at the last call: only the pairs whose tests read a changed node are
  /// found and tested again, with the last call's failing pairs; the others passed and still
  /// do.
  Verification verify_again(const std::vector<Surface>& surfaces, const std::vector<Vec3>& x0,
                            const std::vector<Vec3>& x1, Index first_particle,
                            const std::vector<char>& changed);

 private:
  void build(const std::vector<Surface>& surfaces, Index first_particle, std::size_t nodes);
  Verification run(const std::vector<Surface>& surfaces, const std::vector<Vec3>& x0,
                   const std::vector<Vec3>& x1, Index first_particle,
                   const std::vector<char>* changed);
  Candidates candidate_pairs(const std::vector<Vec3>& x0, const std::vector<Vec3>& x1,
                             const std::vector<char>* changed);
  Candidates step_pairs(const std::vector<Vec3>& x0, const std::vector<Vec3>& x1);
  // The primitives whose tests read a changed node, and the box of them all.
  struct Dirty {
    std::vector<char> node, face, edge;
    Box reach;
    bool any = false;
  };
  Dirty dirty_primitives(const std::vector<Vec3>& x0, const std::vector<Vec3>& x1,
                         const std::vector<char>& changed);
  Candidates dirty_pairs(const Dirty& d, const std::vector<Vec3>& x1);
  Candidates changed_pairs(const std::vector<Vec3>& x0, const std::vector<Vec3>& x1,
                           const std::vector<char>& changed);
  std::vector<char> verdicts(const Candidates& pairs, const std::vector<Vec3>& x0,
                             const std::vector<Vec3>& x1) const;
  const Mesh& mesh_;
  std::unique_ptr<Broadphase> broadphase_;
  BroadphaseInput input_;
  std::vector<Index> face_tet_;
  std::vector<std::array<Index, 2>> edge_faces_;  // the two surface faces at each edge
  bool stale_ = true;                             // the primitives are rebuilt at the next call
  BindingLists lists_;  // candidate pairs of boxes enlarged by the reach, kept while they hold
  std::size_t built_nodes_ = 0;
  Index built_first_particle_ = 0;
  // The last call's failing pairs, (node primitive, face) and (edge, edge), sorted.
  std::vector<std::pair<Index, Index>> failed_vf_, failed_ee_;
};

}  // namespace tc
