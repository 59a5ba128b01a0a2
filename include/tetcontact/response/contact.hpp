// Node–face contact between bodies (seed 001 §3–4): detection from the broadphase's
// candidates, and the contact points the impulse kernel corrects in sequential passes.
#pragma once

#include <array>

#include <memory>
#include <string>
#include <vector>

#include "tetcontact/broadphase/broadphase.hpp"
#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/response/impulse.hpp"

namespace tc {

struct Model;

/// Friction of one body pair (case file `contact.pairs`).
struct PairFriction {
  Index body_a = 0, body_b = 0;
  FrictionMode mode = FrictionMode::slip;
  double coefficient = 0.0;
};

struct ContactSettings {
  std::string broadphase = "fcl_tree";
  double margin = 0.0;  // m, added to every swept box
  int passes = 3;       // sequential correction passes per step
  enum class Order { input, lighter_first } order = Order::lighter_first;
  /// face: the normal of the penetrated face (default); node: minus the averaged normal of
  /// the faces around the penetrating node (seed 001).
  enum class Normal { face, node } normal = Normal::face;
  FrictionMode mode = FrictionMode::slip;  // for body pairs not listed in `pairs`
  double coefficient = 0.0;
  std::vector<PairFriction> pairs;
  /// Seed 001's binding lists: candidates from boxes enlarged by a reach r = 0.2·dx (half of
  /// the 0.4·dx the seed leaves between Rs and 0.75·Rmax; dx the mean tet edge), reused until
  /// a surface node has moved r from where the lists were built. Off: the exact swept boxes
  /// of every step.
  bool binding_lists = true;
  /// Seed 000's edge–edge contact on top of node–face: surface edges of different bodies that
  /// cross during the step (exact CCD) get the reaction of eqs. (11)–(12). Off by default
  /// until the exact test is fast (it costs ~0.2 ms a pair).
  bool edge_edge = false;
};

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

class NodeFaceContact {
 public:
  NodeFaceContact(const Model& model, const ContactSettings& settings);

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

 private:
  Box layer_box(Index face, const State& st, double margin) const;
  const Model& model_;
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
  // Edge pairs in contact last step, with their oriented normal: seed 001 checks contacts
  // already made for staying in contact; an edge pair that has drifted through by round-off
  // would otherwise never be found crossing again.
  std::vector<std::pair<std::pair<Index, Index>, Vec3>> active_edges_;
  BroadphaseInput input_;
  // Binding lists: the candidates, the node positions they were built from, their reach.
  Candidates candidates_;
  std::vector<Vec3> anchor_;
  double reach_ = 0.0;
  bool have_lists_ = false;
  // This step's layer boxes of the faces the lists name, made when first needed.
  std::vector<Box> step_face_box_;
  std::vector<char> have_step_box_;
};

}  // namespace tc
