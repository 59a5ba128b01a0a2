// Contact detection between bodies: node–face (the contact-boundary notes §3) and edge–edge
// (Dobritsa et al. 2019) — the candidates the detection's broadphase lists for the bodies
// (broadphase/contact_candidates.hpp) tested by the narrowphase's predicates and exact CCD. The
// contact points go to the impulse kernel (response/), which corrects them in sequential passes.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tetcontact/broadphase/contact_candidates.hpp"
#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/model/contact_point.hpp"
#include "tetcontact/model/model.hpp"
#include "tetcontact/model/state.hpp"
#include "tetcontact/narrowphase/vertex_face.hpp"

namespace tc {

class Archive;

/// Per-step figures of the narrow phase between bodies.
struct ContactStepStats {
  long candidates = 0;     // node–face pairs listed
  long contacts = 0;       // confirmed node–face contacts
  long edge_contacts = 0;  // confirmed edge–edge contacts
  long edge_candidates = 0;
  double narrowphase_seconds = 0.0;
};

/// The detection's broadphase settings for contact between bodies (and particles with
/// `particles`): the case's method, binding lists and margin, the edges when edge–edge is on,
/// and the layer box of node–face contact.
CandidateSettings candidate_settings(const ContactSettings& contact, bool particles);

class ContactDetection {
 public:
  /// `surfaces`: the run's at the start (the separation and the reach of edge pairs that stay
  /// in contact are set from their mean tet edges). `wave_speed`: the bodies' fastest
  /// reference wave speed (m/s), of which the push speed is a fraction (ContactPoint::push_speed).
  ContactDetection(const Mesh& mesh, const std::vector<Surface>& surfaces,
                   const ContactSettings& settings, double wave_speed);

  /// The surfaces changed (cells turned into particles exposed new faces): the edge pairs in
  /// contact are kept under their edges' new indices (ContactCandidates::surfaces_changed).
  void edges_renamed(const std::vector<Index>& renamed);
  /// What a checkpoint holds of it: the edge pairs in contact.
  void persist(Archive& ar);
  /// The step is taken again, shorter (Simulation::step): the next detect() starts from the
  /// edge pairs in contact at the end of the step before, as the first try did.
  void retake_step() { active_edges_ = step_start_edges_; }

  /// Contacts of this step: every surface node of one body against the faces of the others
  /// (symmetric), from positions xⁿ (st.x) and x* (st.x_star). A candidate is a contact when
  /// the node's predicted position has entered the other body through the face — behind its
  /// plane by at most the altitude of the face's tet, projecting into the face (vertices and
  /// edges included) — or when its path crosses the face during the step (the swept
  /// vertex–face test). Testing only the face's own tet is not enough: a node entering near a
  /// vertex lands in a tet that touches the surface only there. Ordered by node mass (lighter
  /// first) or by (node, face).
  /// The pairs are `candidates.bodies()`, updated for this step.
  std::vector<ContactPoint> detect(const State& st, const ContactCandidates& candidates,
                                   ContactStepStats& stats);

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
  void node_face_contacts(const State& st, const ContactCandidates& candidates,
                          std::vector<ContactPoint>& contacts);
  void edge_edge_contacts(const State& st, const ContactCandidates& candidates,
                          ContactStepStats& stats, std::vector<ContactPoint>& contacts);
  std::optional<ContactPoint> edge_contact(const State& st, const SurfacePrimitives& p, Index ea,
                                           Index eb, const SegmentPoints& cp,
                                           const Vec3* kept) const;
  void set_friction(ContactPoint& c, Index body_a, Index body_b) const;
  const Mesh& mesh_;
  ContactSettings settings_;
  // Edge pairs in contact last step, with their oriented normal: the contact-boundary notes checks
  // contacts already made for staying in contact; an edge pair that has drifted through by
  // round-off would otherwise never be found crossing again.
  std::vector<std::pair<std::pair<Index, Index>, Vec3>> active_edges_;
  std::vector<std::pair<std::pair<Index, Index>, Vec3>> step_start_edges_;  // for retake_step
  double reach_ = 0.0;       // binding_reach of the start's surfaces: edge pairs stay in contact
  double separation_ = 0.0;  // aimed at beyond the rounding margin (ContactSettings::separation)
  double push_speed_ = 0.0;  // ContactPoint::push_speed
  std::vector<Box> step_face_box_;  // this step's layer boxes of the faces the lists name
};

}  // namespace tc
