// The element stage's exchange between processes (distributed runs, `mpirun -np N`): every
// rank updates its own tets (ElementScratch::rank_tets) and receives what the rest of the step
// needs of the others'. With one process (rank_tets empty) each call is the serial path: the
// same sums in the same order, so a distributed run holds the one-process state bit for bit.
#pragma once

#include <functional>
#include <vector>

#include "tetcontact/element/element.hpp"

namespace tc {

// The tets this process updates: in a distributed run its own (ascending), else all.
class MyTets {
 public:
  MyTets(const ElementScratch& scratch, std::size_t tets)
      : list_(scratch.rank_tets.empty() ? nullptr : &scratch.rank_tets[scratch.rank]),
        n_(list_ ? list_->size() : tets) {}
  std::size_t size() const { return n_; }
  std::size_t operator[](std::size_t i) const {
    return list_ ? static_cast<std::size_t>((*list_)[i]) : i;
  }

 private:
  const std::vector<Index>* list_;
  std::size_t n_;
};

/// A distributed run: scratch.rank_tets set.
bool distributed(const ElementScratch& scratch);

/// Block results of a pass appended, in block order, to `into` (the smallest step with the
/// first tet that reaches it; the eroding tets in tet order).
void merge(ForceResult& into, const std::vector<ForceResult>& blocks);

/// Runs `pass` over this process's tets (it fills `blocks`) and returns the serial pass's
/// result: on several ranks combined in one exchange; an inverted element on any rank becomes
/// the same InvertedElement (the lowest tet) on all.
ForceResult collective_pass(const ElementScratch& scratch, std::vector<ForceResult>& blocks,
                            const std::function<void()>& pass);

enum Shared : unsigned {
  k_averages = 1,  // the nodal averages' inputs (volume, tet_energy, tet_averaged)
  k_whole = 2,     // everything a tet holds (for the summary and references at the end)
};

/// The per-tet fields `what` (Shared) of `lists[r]`'s tets sent by rank r to every rank.
void share_tets(ElementScratch& scratch, State& st, unsigned what,
                const std::vector<std::vector<Index>>& lists);

/// Every step: the damaged, destroyed and eroding tets' damage, energy and the state a cell turned
/// into an SPH particle carries, to every rank (fracture reads them).
void share_damaged(const ElementScratch& scratch, State& st, std::vector<Index> eroding);

/// Who sends what for the nodal sums (ElementScratch::rank_nodes, ...), once per mesh.
void build_distribution(const std::vector<Tet>& tets, std::size_t mesh_nodes,
                        ElementScratch& scratch);

/// F_a = Σ of the corner forces of the tets around a, in ascending tet order, on every rank.
void gather_forces(std::size_t mesh_nodes, ElementScratch& scratch, State& st);

}  // namespace tc
