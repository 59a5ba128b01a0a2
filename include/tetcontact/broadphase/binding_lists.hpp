// Binding lists (the contact-boundary notes): the candidate pairs of a broadphase found once from
// boxes enlarged by a reach r, and kept while every point the boxes are built from stays within
// r of where it was when they were found. Then a pair whose boxes (of this step, not enlarged)
// overlap was in the lists: filtering the lists by this step's boxes gives the pairs a fresh
// search gives, and the reach decides only how long the lists last, never what is found.
// One mechanism and one reach rule serve contact, particles and the step's verification.
#pragma once

#include <vector>

#include "tetcontact/broadphase/broadphase.hpp"
#include "tetcontact/mesh/surface.hpp"

namespace tc {

class Archive;

/// The one reach rule: 0.2 of the smallest mean tet edge of the surfaces' bodies (half of the
/// 0.4·dx the contact-boundary notes leave between the search radius and 0.75·Rmax), 0 when
/// no surface has an edge.
double binding_reach(const std::vector<Surface>& surfaces);

class BindingLists {
 public:
  explicit BindingLists(double reach = 0.0) : reach_(reach) {}

  double reach() const { return reach_; }
  bool have() const { return have_; }
  const Candidates& lists() const { return lists_; }

  /// Whether the lists still hold for the points `ids` at positions `x` (every one within the
  /// reach of its anchor); with `only`, for the points i with only[i] set.
  bool holds(const std::vector<Index>& ids, const std::vector<Vec3>& x,
             const std::vector<char>* only = nullptr) const;
  /// Whether point i (of the ids the lists were set for) at x is within the reach of its anchor.
  bool within(std::size_t i, const Vec3& x) const {
    return have_ && i < anchor_.size() && (x - anchor_[i]).squaredNorm() <= reach_ * reach_;
  }
  /// For the step xⁿ → x*: the lists hold at both ends.
  bool hold(const std::vector<Index>& ids, const std::vector<Vec3>& x0,
            const std::vector<Vec3>& x1) const {
    return holds(ids, x0) && holds(ids, x1);
  }
  /// Lists found anew (from boxes enlarged by reach()) for the points `ids` at `x0`.
  void set(Candidates lists, const std::vector<Index>& ids, const std::vector<Vec3>& x0);
  /// The same where the caller keeps the lists itself: only where the points were.
  void anchor(const std::vector<Index>& ids, const std::vector<Vec3>& x0) { set({}, ids, x0); }
  /// The lists are found anew at the next use (the surfaces changed beyond an update).
  void reset() { have_ = false; }
  /// Where each point was when the lists were found.
  const std::vector<Vec3>& anchors() const { return anchor_; }
  /// The lists kept for a changed set of points (their caller renamed them): each point's
  /// anchor, its own for a point that stays.
  void reanchor(std::vector<Vec3> anchors);
  /// What a checkpoint holds of them: the lists, the anchors, whether they are set.
  void persist(Archive& ar);

 private:
  Candidates lists_;
  std::vector<Vec3> anchor_;  // where each point was when the lists were found
  double reach_ = 0.0;
  bool have_ = false;
};

}  // namespace tc
