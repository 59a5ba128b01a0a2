// Planar rigid walls: the momentum exchange of node–face contact (the contact-boundary notes §4)
// with a body of infinite mass.
#pragma once

#include <string>
#include <vector>

#include "tetcontact/model/model.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

struct WallResult {
  Vec3 impulse = Vec3::Zero();  // impulse given to the bodies this step (N s)
  long contacts = 0;            // nodes that received an impulse
};

struct ContactPoint;

/// Contacts of `nodes` and of every particle with the walls: each that would reach or cross a
/// plane within the step, as a contact of weight 1 against a side of infinite mass (no
/// nodes), with the gap d = (xⁿ − p)·n (a particle's less its radius).
std::vector<ContactPoint> wall_contacts(const std::vector<RigidWall>& walls,
                                        const std::vector<Index>& nodes, const State& st);

/// wall_contacts of each wall, a list per wall (the solver's and apply_walls' one source).
std::vector<std::vector<ContactPoint>> wall_contact_lists(const std::vector<RigidWall>& walls,
                                                          const std::vector<Index>& nodes,
                                                          const State& st);

/// What each wall gave after the correction passes over its contacts: the impulse on the
/// bodies, Σ (λ n + tangential), and the contacts that pushed (λ > 0).
std::vector<WallResult> wall_results(const std::vector<std::vector<ContactPoint>>& lists);

/// One correction pass over the walls alone: wall_contact_lists, apply_contact on each (the
/// solver interleaves these passes with the other contacts), wall_results.
/// Corrects the predicted velocities U* of `nodes` against each wall (stage after predict)
/// with the impulse kernel (response/impulse.hpp): the normal impulse
///   λ = m · max(0, −d/τ − U*·n)
/// leaves a node at d ≥ 0 exactly on the plane at tⁿ⁺¹ (one already behind it, d < 0, is
/// stopped). Walls push, never pull. With friction k: Coulomb (stick if that takes at most
/// k λ of tangential impulse, else slide with k λ). The impulses are added to
/// st.wall_impulse and summed per wall.
std::vector<WallResult> apply_walls(const std::vector<RigidWall>& walls,
                                    const std::vector<Index>& nodes, State& st);

}  // namespace tc
