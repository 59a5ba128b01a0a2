#include "tetcontact/solver/simulation.hpp"

#include <cmath>
#include <sstream>

#include "tetcontact/solver/integrator.hpp"

namespace tc {
namespace {

class StageTimer {
 public:
  explicit StageTimer(double& slot) : slot_(slot), start_(std::chrono::steady_clock::now()) {}
  ~StageTimer() {
    slot_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  double& slot_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

double& StepProfile::operator[](const std::string& name) {
  for (auto& [n, s] : stages)
    if (n == name) return s;
  stages.emplace_back(name, 0.0);
  return stages.back().second;
}

double StepProfile::total() const {
  double t = 0.0;
  for (const auto& s : stages) t += s.second;
  return t;
}

Simulation::Simulation(Model model, SolverSettings settings)
    : model_(std::move(model)), settings_(settings) {
  const Mesh& mesh = model_.mesh;
  const std::size_t n = mesh.x.size(), m = mesh.tets.size();
  State& st = state_;
  st.x = mesh.x;
  st.v = model_.initial_velocity;
  st.v_star.assign(n, Vec3::Zero());
  st.x_star.assign(n, Vec3::Zero());
  st.f.assign(n, Vec3::Zero());
  st.bc_impulse.assign(n, Vec3::Zero());
  st.m.assign(n, 0.0);
  st.vol0 = tet_volumes(mesh.x, mesh.tets);
  st.vol = st.vol0;
  st.s.assign(m, Sym6{0, 0, 0, 0, 0, 0});
  st.p.assign(m, 0.0);
  st.e_int.assign(m, 0.0);
  st.tet_material.resize(m);
  // Lumped masses: a quarter of each tet's mass on each of its nodes.
  for (std::size_t t = 0; t < m; ++t) {
    st.tet_material[t] = model_.body_material[mesh.tet_body[t]];
    const double quarter = 0.25 * model_.materials[st.tet_material[t]].density * st.vol0[t];
    for (Index k : mesh.tets[t]) st.m[k] += quarter;
  }

  modules_ = {"integrator:central_difference", "elements:linear_tet", "material:elastic"};
  if (!model_.constraints.empty()) modules_.push_back("boundary_conditions");
  modules_.push_back("diagnostics:balance");

  for (const char* stage : {"predict", "balance", "output", "commit", "elements"})
    profile_[stage] = 0.0;
  elements_stage();  // F^0 and τ^0; the first step then uses τ_v = τ/2
  st.dt_prev = 0.0;
}

void Simulation::add_observer(Observer* observer, const std::string& module_name) {
  observers_.push_back(observer);
  modules_.push_back(module_name);
}

bool Simulation::done() const {
  return state_.t >= settings_.end_time;
}

// The step, in the seed's order: predict, (contact corrections), commit.
void Simulation::step() {
  if (state_.step >= settings_.max_steps) {
    std::ostringstream os;
    os << "max_steps (" << settings_.max_steps << ") reached at t = " << state_.t
       << " s before end_time " << settings_.end_time << " s";
    throw RunFailure(os.str());
  }
  {
    StageTimer t(profile_["predict"]);
    predict_stage();
  }  // U*, x* (eqs. 2, 3)
  // Contact corrections of U* come here; no contact stage exists in this version.
  {
    StageTimer t(profile_["balance"]);
    sample_stage();
  }  // energy, momentum at t^n
  {
    StageTimer t(profile_["output"]);
    output_stage();
  }  // observers see t^n
  {
    StageTimer t(profile_["commit"]);
    commit_stage();
  }  // U^{n+1}, x^{n+1} (eq. 1)
  {
    StageTimer t(profile_["elements"]);
    elements_stage();
  }  // σ^{n+1}, F^{n+1}, next τ
}

void Simulation::finish() {
  {
    StageTimer t(profile_["predict"]);
    predict_stage();
  }
  {
    StageTimer t(profile_["balance"]);
    sample_stage();
  }
  {
    StageTimer t(profile_["output"]);
    output_stage();
  }
}

void Simulation::predict_stage() {
  predict(state_, model_.constraints);
}

double Simulation::balance_error(const Sample& s) const {
  if (energy_scale_ <= 0.0) return 0.0;
  return std::abs(s.total - s.boundary_work - first_.total) / energy_scale_;
}

void Simulation::sample_stage() {
  Sample s = sample_balance(state_, have_sample_ ? &last_ : nullptr);
  if (!std::isfinite(s.kinetic) || !std::isfinite(s.momentum.sum())) {
    std::ostringstream os;
    os << "non-finite velocity at t = " << state_.t << " s (step " << state_.step << ")";
    throw RunFailure(os.str());
  }
  if (!have_sample_) first_ = s;
  have_sample_ = true;
  energy_scale_ = std::max(
      {energy_scale_, std::abs(first_.total), std::abs(s.boundary_work), s.kinetic + s.internal});
  s.balance_error = balance_error(s);
  balance_error_max_ = std::max(balance_error_max_, s.balance_error);
  last_ = s;
}

void Simulation::output_stage() {
  for (Observer* o : observers_) o->observe(state_, last_);
}

void Simulation::commit_stage() {
  commit(state_);
}

void Simulation::elements_stage() {
  State& st = state_;
  try {
    if (st.step > 0) update_stress(model_.mesh.tets, model_.materials, st.dt_prev, st);
    const ForceResult r = compute_forces(model_.mesh.tets, model_.materials, st);
    critical_tet_ = r.critical_tet;
    // No step is shortened to land on end_time: an abrupt change of τ costs the leapfrog
    // its exact energy balance (see sample_balance), so the run ends at the first step at or
    // after end_time and reports the time reached.
    st.dt = settings_.cfl * r.dt_stable;
    if (!(st.dt > 0.0) || !std::isfinite(st.dt)) {
      std::ostringstream os;
      os << "time step " << st.dt << " s is not positive and finite";
      throw RunFailure(os.str());
    }
  } catch (const InvertedElement& e) {
    rethrow_with_body(e);
  }
}

void Simulation::rethrow_with_body(const InvertedElement& e) const {
  const Index body = model_.mesh.tet_body[e.tet];
  const BodyRange& b = model_.mesh.bodies[body];
  std::ostringstream os;
  os << "body '" << b.name << "', tet " << e.tet - b.tet_begin << ": " << e.what()
     << " at t = " << state_.t << " s (step " << state_.step << ")";
  throw InvertedElement(e.tet, os.str());
}

}  // namespace tc
