#include "tetcontact/broadphase/binding_lists.hpp"
#include "tetcontact/model/persist.hpp"

#include <algorithm>

namespace tc {

double binding_reach(const std::vector<Surface>& surfaces) {
  return 0.2 * smallest_mean_edge(surfaces);
}

bool BindingLists::holds(const std::vector<Index>& ids, const std::vector<Vec3>& x,
                         const std::vector<char>* only) const {
  if (!have_ || anchor_.size() != ids.size()) return false;
  const double r2 = reach_ * reach_;
  for (std::size_t i = 0; i < ids.size(); ++i)
    if ((!only || (*only)[i]) && (x[ids[i]] - anchor_[i]).squaredNorm() > r2) return false;
  return true;
}

void BindingLists::set(Candidates lists, const std::vector<Index>& ids,
                       const std::vector<Vec3>& x0) {
  lists_ = std::move(lists);
  anchor_.resize(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) anchor_[i] = x0[ids[i]];
  have_ = true;
}

void BindingLists::reanchor(std::vector<Vec3> anchors) {
  anchor_ = std::move(anchors);
  have_ = true;
}

void BindingLists::persist(Archive& ar) {
  ar(lists_.node_face, lists_.edge_edge, anchor_, reach_, have_);
}

}  // namespace tc
