// Rigid impact zones (Provot 1997; Bridson, Fedkiw & Anderson 2002; Harmon et al. 2008): the
// fail-safe of the step's verification (verify/verify.hpp). The nodes of the pairs that
// still fail after the correction passes are merged into zones (a union–find over nodes); each
// zone's nodes then move this step with the zone's rigid velocity field
//   U_i = V + ω × (x_i − c),   M V = Σ m_i u_i,   I ω = L = Σ m_i (x_i − c) × (u_i − V),
// c the zone's centre of mass, I its inertia tensor about c (pseudo-inverse when the zone is
// collinear), u_i the velocities the passes left. Linear and angular momentum are kept; the
// kinetic energy can only fall (U is the mass-weighted projection of u onto rigid fields), and
// the impulses m_i (U_i − u_i) go to the contact ledger, so what the zone removes is booked as
// contact work.
//
// Why a zone removes its failures: with linear paths, x_i(t) = x_i + t τ U_i is the affine map
// x ↦ x + t τ (V + Ω (x − c)) (Ω the cross-product matrix of ω), whose linear part I + t τ Ω
// has determinant 1 + (t τ |ω|)² > 0: an affine bijection at every time, which keeps every
// incidence (a point in a triangle, a segment through a face, two segments meeting) as it was
// at the start. In exact arithmetic a zone holding every node a failing test reads cannot fail.
// In doubles, xⁿ + τ U is rounded and a touching pair may end one ulp through: such a zone
// then moves by an exact translation (every node by the same vector d ≈ τ V, rounded per axis
// to a multiple of the coarsest ulp of the zone's coordinates, an axis left out where a sum
// would round: x + d is then exact, and all relative positions are kept bit for bit), and if a
// failure remains inside it, the zone is frozen (its nodes keep xⁿ). In both the velocities
// are the zone's rigid ones, so both momenta are kept; the motion that differs from τ U (the
// rotation's part, or all of it when frozen) is not booked as work. A translation or the
// identity cannot fail from a state that did not. Each round merges zones, grows one or
// escalates one (rigid → translated → frozen), so the loop ends.
#pragma once

#include <array>
#include <vector>

#include "tetcontact/model/state.hpp"

namespace tc {

class ImpactZones {
 public:
  /// Forgets the zones (a new step); `node_count` sizes the union–find.
  void reset(std::size_t node_count);
  /// Puts the nodes in one zone (merging the zones they are in). Returns whether they already
  /// were all in one zone.
  bool merge(const Index* nodes, int count);
  /// Whether the nodes are all in one zone already.
  bool same_zone(const Index* nodes, int count) const;
  enum class Motion { rigid, translated, frozen };
  /// The zone of `node` moves less freely: rigid → translated → frozen.
  void escalate(Index node);
  Motion motion(Index node) const;
  /// Sets the velocities of every zone's nodes to the zone's rigid field computed from `u`
  /// (the velocities before any zone) at positions x; the change of each node's momentum is
  /// added to `ledger`.
  void apply(const std::vector<Vec3>& u, State& st, std::vector<Vec3>& ledger);

  /// The zones: their nodes (sorted), and how each moves.
  struct Zone {
    std::vector<Index> nodes;
    Motion motion = Motion::rigid;
  };
  std::vector<Zone> zones() const;

 private:
  Index find(Index n) const;
  mutable std::vector<Index> parent_;     // −1: in no zone; a root is its own parent
  std::vector<char> level_root_;          // Motion of each root
  std::vector<Index> touched_;            // nodes in a zone, for reset
  mutable std::vector<Index> root_slot_;  // zones()'s scratch, all −1
};

/// The translation nearest d that moves every one of `nodes` exactly: per axis, d rounded to a
/// multiple of the coarsest ulp of the nodes' coordinates, or 0 on an axis where x + d would
/// still round for some node (checked exactly: the sum's rounding error is 0). `exact`, when
/// given, says per axis whether the shift returned is exact (false: no exact shift was found).
Vec3 exact_translation(const std::vector<Vec3>& x, const std::vector<Index>& nodes, const Vec3& d,
                       std::array<bool, 3>* exact = nullptr);

}  // namespace tc
