// Planar rigid walls: the momentum exchange of node–face contact (seed 001 §4) with a body
// of infinite mass.
#pragma once

#include <string>
#include <vector>

#include "tetcontact/solver/state.hpp"

namespace tc {

struct RigidWall {
  std::string name;
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  // unit, pointing to the side the bodies are on
  double friction = 0.0;        // Coulomb coefficient k (0: ideal slip)
};

struct WallResult {
  Vec3 impulse = Vec3::Zero();  // impulse given to the bodies this step (N s)
  long contacts = 0;            // nodes that received an impulse
};

/// Corrects the predicted velocities U* of `nodes` against each wall (stage after predict).
/// A node at signed distance d = (xⁿ − p)·n ≥ 0 whose normal velocity would carry it
/// through the plane within the step receives the normal impulse
///   λ = m · max(0, −d/τ − U*·n),
/// the momentum exchange with an infinite mass that leaves it exactly on the plane at tⁿ⁺¹
/// (a node already behind the plane, d < 0, is stopped: λ = m · max(0, −U*·n)). Walls push,
/// never pull. With friction k the tangential velocity is removed if that takes an impulse
/// of at most k λ (stick), else reduced by k λ / m (Coulomb slip). The impulses are added to
/// st.wall_impulse and summed per wall.
std::vector<WallResult> apply_walls(const std::vector<RigidWall>& walls,
                                    const std::vector<Index>& nodes, State& st);

}  // namespace tc
