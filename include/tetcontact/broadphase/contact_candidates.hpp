// The detection stage's one broadphase update: the surface nodes, faces and edges of every body
// and the particles, boxed over the step xⁿ → x*, on binding lists (the bodies' and the
// particles', each found anew when its points have moved past the reach, and updated across a
// conversion). The narrow phases (node–face and edge–edge between bodies, particle–face and
// particle–particle) then test the pairs it lists for them.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tetcontact/broadphase/binding_lists.hpp"
#include "tetcontact/broadphase/broadphase.hpp"
#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

class Archive;

/// The surface primitives of all bodies, in surface order (the numbering every list uses).
struct SurfacePrimitives {
  std::vector<Index> nodes, node_body, node_surface, node_slot;  // slot: index in its surface
  std::vector<Face> faces;
  std::vector<Index> face_body, face_tet;
  std::vector<Edge> edges;  // only when edge–edge pairs are asked for
  std::vector<Index> edge_body;
  std::vector<std::array<Index, 2>> edge_faces;  // the two faces at each edge (into faces)
};

SurfacePrimitives surface_primitives(const std::vector<Surface>& surfaces, bool edges);

/// The box of the region where node–face contact accepts a node for a face (narrowphase's
/// behind_face): the prism from the face down to the altitude of its tet, at xⁿ and x*, widened
/// by `rim` times its longest edge and by `margin`. It holds the face itself at both ends.
Box layer_box(const Face& face, const Tet& tet, const std::vector<Vec3>& x0,
              const std::vector<Vec3>& x1, double rim, double margin);

/// What is listed. Bodies: node–face pairs (and edge–edge pairs with `edges`) between different
/// bodies, a face's box its layer box (`rim`, `margin`). Particles: each particle against every
/// face and every other particle, a particle's box its path inflated by its radius; with
/// `kernel_reach` k > 0 (SPH particles, State::sph.h), also every face within k h_i of particle
/// i and every pair within k (h_i + h_j) / 2 (its box for faces inflated by max(radius, k h_i),
/// for pairs by k h_i / 2).
struct CandidateSettings {
  std::string broadphase = "fcl_tree";
  bool binding_lists = true;
  bool bodies = true;
  bool edges = false;
  bool particles = false;
  bool particle_pairs = true;  // with particles: their pairs with each other too
  double kernel_reach = 0.0;   // SPH particles: the reach of their kernel over h
  double margin = 0.0;         // m, added to the bodies' boxes
  double rim = 0.0;            // of the layer box
  /// The step's verification takes its pairs from these lists (verify/verify.hpp): the edges
  /// are listed even without edge–edge contact, and the lists are found with boxes enlarged by
  /// the reach even without binding lists (which then only decide that every update searches).
  bool verify = false;
};

/// Pairs of the lists for one narrow phase, with the faces they name (sorted, each once).
struct CandidateLists : Candidates {
  std::vector<Index> faces;
};

/// Figures of one update.
struct CandidateStats {
  bool rebuilt = false;                             // the broadphase ran
  double seconds = 0.0;                             // the whole update
  double build_seconds = 0.0, query_seconds = 0.0;  // the broadphase's own split
};

class ContactCandidates {
 public:
  /// The binding lists' reach is binding_reach(surfaces) of these (the start's) surfaces, or 0
  /// without binding lists; `mesh` gives each face's tet (its layer box).
  ContactCandidates(const Mesh& mesh, const std::vector<Surface>& surfaces,
                    const CandidateSettings& settings);

  /// The surfaces changed (cells turned into particles), at the positions st.x: primitives
  /// rebuilt. Each part's lists that hold at st.x are updated: the pairs of the primitives that
  /// stay renamed, the new primitives and the new or joined particles (whose radius changed)
  /// paired with the rest and anchored at st.x; the others, and SPH particles' lists, are found
  /// anew at the next update. Returns the new index of each former edge (−1: no longer a surface
  /// edge).
  std::vector<Index> surfaces_changed(const std::vector<Surface>& surfaces, const State& st);

  /// The step's update from xⁿ (st.x) and x* (st.x_star). The bodies' lists are kept while
  /// every surface node is within the reach of where it was at their search (at both ends of the
  /// step), the particles' while every particle and surface node is and no particle was added;
  /// the lists that ran out are found anew from the boxes enlarged by the reach (the
  /// particles' against the faces near them). A pair whose boxes of this step overlap is then in
  /// the lists; the narrow phases skip listed pairs whose boxes of the step do not overlap, and
  /// find what a fresh search finds.
  CandidateStats update(const State& st);
  /// The particles' lists for the positions st.x alone (the SPH stage's, after the step's
  /// commit): kept when every particle and surface node is within the reach of where it was at
  /// their search and no particle was added, else found anew at st.x (the next update then
  /// checks them at both ends of its step). `rebuilt` says whether a search ran.
  const CandidateLists& particles_at(const State& st, bool* rebuilt = nullptr);

  /// The lists for the step's verification, from xⁿ (st.x, as at the last update) to x1: each
  /// part (bodies, particles) whose points are not all within the reach of where they were at
  /// its search (with `moved`, of those node ids alone, the others as at the last call) is
  /// found anew for xⁿ → x1. Then the listed pairs whose boxes of xⁿ → x1 overlap are the
  /// pairs a fresh search finds. Returns whether a search ran (the lists changed).
  bool lists_for(const State& st, const std::vector<Vec3>& x1,
                 const std::vector<Index>* moved = nullptr);
  /// Counts the searches and primitive changes: a caller keeping data per listed pair rebuilds
  /// it when this changes.
  long version() const { return version_; }
  /// What a checkpoint holds of it: the lists and where they were found. Reading it back takes
  /// the primitives of `surfaces` (the checkpoint's, State::surfaces).
  void persist(Archive& ar, const std::vector<Surface>& surfaces);

  const SurfacePrimitives& primitives() const { return prims_; }
  /// Each mesh node's index in primitives().nodes (−1: not on a surface).
  const std::vector<Index>& node_slots() const { return node_slot_; }
  /// (surface node, face) and (edge, edge) between bodies; indices into primitives().
  const CandidateLists& bodies() const { return bodies_; }
  /// (particle, face) (node_face) and (particle, particle) (edge_edge); particle i is node
  /// st.first_particle + i.
  const CandidateLists& particles() const { return particles_; }
  /// The reach of the binding lists (m; 0 without them).
  double reach() const { return body_lists_.reach(); }
  const CandidateSettings& settings() const { return settings_; }
  const Broadphase& broadphase() const { return *broadphase_; }

 private:
  bool bodies_hold(const State& st) const;
  bool particles_hold(const State& st) const;
  // Each part's lists at x1: every listed point (or each of `moved`) within the reach.
  bool hold_at(const State& st, bool bodies, const std::vector<Vec3>& x1,
               const std::vector<Index>* moved) const;
  // The step x0 = st.x → x1.
  void search(const State& st, bool bodies, bool particles, const std::vector<Vec3>& x1);
  const Mesh& mesh_;
  CandidateSettings settings_;
  std::unique_ptr<Broadphase> broadphase_;
  SurfacePrimitives prims_;
  // Where the points were at the last search of each part's lists (the lists: bodies_,
  // particles_): the surface nodes; the particles, then the surface nodes.
  BindingLists body_lists_, particle_lists_;
  std::vector<Index> particle_anchored_;
  std::vector<Index> node_slot_;  // each mesh node's index in prims_.nodes (−1: not on a surface)
  Index particles_listed_ = 0;
  // Each particle's radius as the particles' lists know it (a join changes it).
  std::vector<double> listed_radius_;
  long version_ = 0;
  CandidateLists bodies_, particles_;
};

}  // namespace tc
