// Contact detection between bodies: node–face (the contact-boundary notes §3) and edge–edge
// (Dobritsa et al. 2019) — the broadphase's candidates (binding lists) tested by the
// narrowphase's predicates and exact CCD. The contact points go to the impulse kernel
// (response/), which corrects them in sequential passes.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tetcontact/broadphase/binding_lists.hpp"
#include "tetcontact/broadphase/broadphase.hpp"
#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/model/contact_point.hpp"
#include "tetcontact/model/model.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

/// Per-step figures of the contact stage.
struct ContactStepStats {
  long candidates = 0;     // node–face pairs from the broadphase
  long contacts = 0;       // confirmed node–face contacts
  long edge_contacts = 0;  // confirmed edge–edge contacts
  long edge_candidates = 0;
  bool rebuilt = false;  // the candidate lists were rebuilt this step
  double broadphase_seconds = 0.0, narrowphase_seconds = 0.0;
  double build_seconds = 0.0, query_seconds = 0.0;  // the broadphase's own split
};

class ContactDetection {
 public:
  /// `surfaces` are the live surfaces of the run (owned by the caller, read at every step):
  /// after they change, call surfaces_changed().
  ContactDetection(const Mesh& mesh, const std::vector<Surface>& surfaces,
                   const ContactSettings& settings);

  /// The surfaces changed (cells turned into particles exposed new faces): the primitives are
  /// rebuilt; the edge pairs in contact are kept (by their nodes); the binding lists are
  /// rebuilt at the next step.
  void surfaces_changed();

  /// Contacts of this step: every surface node of one body against the faces of the others
  /// (symmetric), from positions xⁿ (st.x) and x* (st.x_star). A candidate is a contact when
  /// the node's predicted position has entered the other body through the face — behind its
  /// plane by at most the altitude of the face's tet, projecting into the face (vertices and
  /// edges included) — or when its path crosses the face during the step (the swept
  /// vertex–face test). Testing only the face's own tet is not enough: a node entering near a
  /// vertex lands in a tet that touches the surface only there. Ordered by node mass (lighter
  /// first) or by (node, face).
  std::vector<ContactPoint> detect(const State& st, ContactStepStats& stats);

  const Broadphase& broadphase() const { return *broadphase_; }
  /// The separation contacts aim at beyond the rounding margin (m).
  double separation() const { return separation_; }

  /// A contact point for a pair the step's verification found failing over the motion
  /// xⁿ = st.x → `x1`: a vertex `node` of body `node_body` against the face `face`
  /// of body `face_body` (nodes in the surface's outward order), or the edge `a` of body
  /// `body_a` against the edge `b`. Apart at xⁿ: where they first meet during the motion (the
  /// exact time of impact t*), the normal the face's or the edges' common perpendicular at t*,
  /// signed to point from B to A at xⁿ, the gap the distance along it at xⁿ
  /// (narrowphase/contact.cpp says why). Touching at xⁿ: at their closest points at xⁿ, the face's
  /// outward normal, or for edges their common perpendicular oriented against the outward normals
  /// of the faces at them (gap 0). Friction as for a detected contact of the pair; `restore`,
  /// aiming as a detected contact does (the rounding margin and the stand-off). nullopt when no
  /// normal can be found (degenerate primitives touching). `outward_a`, `outward_b`: the sums of
  /// the outward normals of the faces at each edge.
  std::optional<ContactPoint> vertex_face_point(const State& st, const std::vector<Vec3>& x1,
                                                Index node, const Face& face, Index node_body,
                                                Index face_body) const;
  std::optional<ContactPoint> edge_edge_point(const State& st, const std::vector<Vec3>& x1,
                                              const Edge& a, const Edge& b, Index body_a,
                                              Index body_b, const Vec3& outward_a,
                                              const Vec3& outward_b) const;

 private:
  void build_primitives();
  void refresh_lists(const State& st, ContactStepStats& stats);
  void node_face_contacts(const State& st, std::vector<ContactPoint>& contacts);
  void edge_edge_contacts(const State& st, ContactStepStats& stats,
                          std::vector<ContactPoint>& contacts);
  Box layer_box(Index face, const State& st, double margin) const;
  void set_friction(ContactPoint& c, Index body_a, Index body_b) const;
  const Mesh& mesh_;
  const std::vector<Surface>& surfaces_;
  ContactSettings settings_;
  std::unique_ptr<Broadphase> broadphase_;
  // Surface primitives of all bodies.
  std::vector<Index> nodes_, node_body_, node_surface_, node_slot_;
  std::vector<Face> faces_;
  std::vector<Index> face_body_, face_tet_;
  std::vector<Edge> edges_;
  std::vector<Index> edge_body_;
  std::vector<std::array<Index, 2>>
      edge_faces_;  // the two surface faces at each edge (into faces_)
  // Edge pairs in contact last step, with their oriented normal: the contact-boundary notes checks
  // contacts already made for staying in contact; an edge pair that has drifted through by
  // round-off would otherwise never be found crossing again.
  std::vector<std::pair<std::pair<Index, Index>, Vec3>> active_edges_;
  BroadphaseInput input_;
  BindingLists lists_;       // the candidates, kept while the surface nodes stay within reach
  double separation_ = 0.0;  // aimed at beyond the rounding margin (ContactSettings::separation)
  // This step's layer boxes of the faces the lists name (binding lists).
  std::vector<Index> listed_faces_;
  std::vector<Box> step_face_box_;
};

}  // namespace tc
