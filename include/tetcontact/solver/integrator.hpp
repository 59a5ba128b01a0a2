// Explicit central difference, Dobritsa et al. eqs. (1)–(3).
#pragma once

#include <vector>

#include "tetcontact/model/model.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

/// Predicted ("free surface") velocities and positions:
///   Dobritsa et al. eq. (2): U*_k = U_k^n + τ_v F_k^n / m_k
///   Dobritsa et al. eq. (3): x*_k = x_k^n + U*_k τ
/// with τ_v = (τ^{n-1/2} + τ^{n+1/2}) / 2 the centred step of the variable-step central
/// difference (τ_v = τ when the step is constant; τ/2 on the first step, which starts the
/// leapfrog from velocities given at t = 0). Prescribed velocity components then overwrite
/// U*, and the impulse that took is recorded in st.bc_impulse.
void predict(State& st, const std::vector<VelocityConstraint>& constraints);

/// The prescribed components again after the corrections (walls and contacts act on every
/// node; a prescribed component is not theirs to change): each one set back, the impulse that
/// took added to st.bc_impulse. x* is not moved (the corrections do not move it either).
void hold_constraints(State& st, const std::vector<VelocityConstraint>& constraints);

/// Committed update, Dobritsa et al. eq. (1) with the contact reactions already folded into U*:
///   U^{n+1} = U*,   x^{n+1} = x^n + U^{n+1} τ.
void commit(State& st);

}  // namespace tc
