// Interpenetration of bodies, measured independently of the contact code (the
// diagnostics stage): boundary nodes inside another body's tets, and boundary edges of one
// body crossing boundary faces of another, decided with exact predicates (CGAL).
#pragma once

#include <memory>
#include <vector>

#include "tetcontact/broadphase/binding_lists.hpp"
#include "tetcontact/broadphase/broadphase.hpp"
#include "tetcontact/model/model.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

class Archive;

struct Penetration {
  long nodes_inside = 0;            // boundary nodes inside another body (depth > 0)
  double max_depth = 0.0;           // m: distance of such a node to that body's surface
  double max_depth_over_h = 0.0;    // the same over that body's mean tet edge length
  long crossings = 0;               // boundary edges crossing another body's boundary faces
  double max_crossing_depth = 0.0;  // m: the shortest move that undoes a crossing: the
                                    // crossing point's distance to the face's boundary, or
                                    // the edge's nearer end's distance past the face's plane
  long particles_inside = 0;        // particles whose centre is inside a body
  double max_particle_depth = 0.0;  // m: such a centre's distance to that body's surface
  std::vector<double> node_depth;   // per node (0 unless inside another body), m
  // The bodies of the deepest node inside (its own, the one it is in) and of the deepest
  // crossing (the edge's, the face's); −1 when there is none.
  Index deepest_node_body = -1, deepest_in_body = -1;
  Index crossing_edge_body = -1, crossing_face_body = -1;
};

/// Raises each of `largest`'s maxima (counts and depths, not the per-node depths or the
/// bodies) to `p`'s where p's is larger: the run's largest over its samples.
void keep_largest(Penetration& largest, const Penetration& p);
void persist(Archive& ar, Penetration& p);

/// Exact predicates (CGAL's, in penetration_cgal.cpp): p in the closed tet (a, b, c, d);
/// segment (p, q) passes through the interior of triangle (a, b, c), its ends strictly on
/// opposite sides of the triangle's plane (an edge lying in the face, or touching it at its
/// boundary, does not cross it).
bool exact_point_in_tet(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
bool exact_segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                                    const Vec3& c);
/// p lies in the open tet (a, b, c, d): not on its boundary.
bool exact_point_strictly_in_tet(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                 const Vec3& d);
/// p lies on the closed, non-degenerate triangle (a, b, c).
bool exact_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

class PenetrationProbe {
 public:
  explicit PenetrationProbe(const Model& model);
  /// Measures at positions x. A node's depth is its distance to the nearest boundary face of
  /// the body it is inside, searched within two mean edge lengths (a deeper node reports
  /// that bound); a node exactly on one of those faces touches and is not inside (its
  /// floating-point distance, ~1e-19 m, is not a depth).
  Penetration measure(const std::vector<Vec3>& x);
  /// At a state, with its surfaces (State::surfaces): cells turned into particles are left
  /// out, and particle centres inside any body are measured as nodes are (particles_inside,
  /// max_particle_depth).
  Penetration measure(const State& st);
  /// Searches of the binding lists so far (the nodes-in-tets search and the edges-across-faces
  /// one each count).
  long searches() const { return searches_; }
  /// What a checkpoint holds of it: its lists and the primitives they were found for.
  void persist(Archive& ar);

 private:
  Penetration measure(const std::vector<Vec3>& x, const std::vector<Surface>& surfaces,
                      const std::vector<Damage>& damage, Index first_particle);
  std::vector<Index> bodies_holding(const std::vector<Vec3>& x);
  void measure_depths(const std::vector<Vec3>& x, const std::vector<Index>& inside_body,
                      Index first_particle, Penetration& r);
  void measure_crossings(const std::vector<Vec3>& x, Penetration& r);
  bool primitives_changed(const std::vector<Vec3>& x, const std::vector<Surface>& surfaces,
                          const std::vector<Damage>& damage, Index first_particle);
  const Model& model_;
  std::unique_ptr<Broadphase> broadphase_;
  // Binding lists of the two searches over every node (nodes in tets) and over the surface
  // (edges across faces), from boxes enlarged by the reach, kept while the points stay within
  // it and the primitives are the same (a probe every step or every few steps searches rarely).
  BindingLists inside_lists_, cross_lists_;
  long searches_ = 0;
  std::vector<Index> all_nodes_;  // 0 … n − 1: the points of the tets' boxes
  std::vector<Index> in_tet_;     // the tet of each "face" of the nodes-in-tets search
  std::vector<Index> nodes_, node_body_;
  std::vector<Edge> edges_;
  std::vector<Index> edge_body_;
  std::vector<Face> faces_;
  std::vector<Index> face_body_;
  std::vector<double> body_h_;  // mean tet edge per body
};

}  // namespace tc
