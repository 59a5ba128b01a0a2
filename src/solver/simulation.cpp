#include "tetcontact/solver/simulation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "tetcontact/io/files.hpp"
#include "tetcontact/model/persist.hpp"
#include "tetcontact/parallel/mpi.hpp"
#include "tetcontact/parallel/parallel.hpp"
#include "tetcontact/response/heat.hpp"
#include "tetcontact/solver/integrator.hpp"
#include "tetcontact/sph/kernel.hpp"

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

State initial_state(const Model& model) {
  const Mesh& mesh = model.mesh;
  const std::size_t n = mesh.x.size(), m = mesh.tets.size();
  State st;
  st.x = mesh.x;
  st.surfaces = model.surfaces;
  st.first_particle = static_cast<Index>(n);
  st.v = model.initial_velocity;
  st.v.resize(n, Vec3::Zero());
  for (auto* field :
       {&st.v_star, &st.x_star, &st.f, &st.bc_impulse, &st.wall_impulse, &st.contact_impulse})
    field->assign(n, Vec3::Zero());
  st.m.assign(n, 0.0);
  st.vol0 = tet_volumes(mesh.x, mesh.tets);
  st.vol = st.vol0;
  st.s.assign(m, Sym6{0, 0, 0, 0, 0, 0});
  for (auto* field : {&st.p, &st.q, &st.e_int, &st.eps_p, &st.ductile, &st.ductile_floor,
                      &st.w_plastic, &st.w_viscous, &st.sound2, &st.trace_d})
    field->assign(m, 0.0);
  st.tet_material.resize(m);
  st.damage.assign(m, Damage::intact);
  st.temperature.assign(m, 0.0);
  // Lumped masses: a quarter of each tet's mass on each of its nodes.
  for (std::size_t t = 0; t < m; ++t) {
    st.tet_material[t] = model.body_material[mesh.tet_body[t]];
    st.temperature[t] = model.materials[st.tet_material[t]].start_temperature();
    const double quarter = 0.25 * model.materials[st.tet_material[t]].density * st.vol0[t];
    for (Index k : mesh.tets[t]) st.m[k] += quarter;
  }
  init_sound_speed(model.materials, st);
  return st;
}

Simulation::Simulation(Model model, SolverSettings settings)
    : model_(std::move(model)),
      settings_(settings),
      state_(initial_state(model_)),
      elements_(model_.element) {
  // Threads: all the cores by default; processes sharing a machine share its cores.
  parallel::set_threads(settings_.threads > 0 || mpi::local_ranks() == 1
                            ? settings_.threads
                            : std::max(1, parallel::hardware_threads() / mpi::local_ranks()));
  State& st = state_;
  // The symmetry planes each node lies on (their constraints: response/heat.hpp).
  for (const VelocityConstraint& vc : model_.constraints) {
    if (!vc.mirror) continue;
    node_planes_.resize(model_.mesh.node_count(), 0);
    for (const Index n : vc.nodes) ++node_planes_[n];
  }
  // The modules this case needs, and nothing else.
  modules_ = {"integrator:central_difference", "elements:linear_tet"};
  bool plastic = false, anp = false, thermal = false;
  bool eos[3] = {false, false, false};   // EosKind's values in use
  bool laws[3] = {false, false, false};  // StrengthModel's values in use
  for (std::size_t k = 0; k < model_.materials.size(); ++k) {
    const Material& mk = model_.materials[k];
    plastic = plastic || mk.plastic();
    if (mk.plastic()) laws[static_cast<int>(mk.strength)] = true;
    thermal = thermal || mk.thermal();
    eos[static_cast<int>(mk.eos)] = true;
    anp = anp || (k < model_.element.average_nodal_pressure.size() &&
                  model_.element.average_nodal_pressure[k]);
  }
  modules_.push_back(plastic ? "material:elastic_plastic" : "material:elastic");
  for (int l = 0; l < 3; ++l)
    if (laws[l])
      modules_.push_back("strength:" +
                         std::string(name_of(k_strength_names, static_cast<StrengthModel>(l))));
  if (thermal) modules_.push_back("material:temperature");
  for (int e = 0; e < 3; ++e)
    if (eos[e])
      modules_.push_back("eos:" + std::string(name_of(k_eos_names, static_cast<EosKind>(e))));
  if (anp) modules_.push_back("elements:average_nodal_pressure");
  if (model_.element.viscosity_linear > 0 || model_.element.viscosity_quadratic > 0)
    modules_.push_back("elements:bulk_viscosity");
  if (model_.element.fracture) modules_.push_back("elements:fracture");
  if (model_.element.fracture && model_.particles) {
    fragmentation_ = std::make_unique<Fragmentation>(
        model_.mesh, model_.fragment_clusters ? Fragments::clusters : Fragments::cells,
        model_.sph_debris ? model_.sph.smoothing : 0.0);
    particle_contact_ = std::make_unique<ParticleContact>(
        model_.sph_debris && model_.sph.faces ? 0.0 : 1.0, !model_.sph_debris);
    modules_.push_back("fracture:particles");
    if (model_.fragment_clusters) modules_.push_back("fracture:clusters");
    if (model_.sph_debris) {
      // SPH particles meet each other through their kernel; the bodies' faces through it too
      // (fracture.sph.faces: kernel) and by contact.
      std::vector<sph::MirrorPlane> planes;
      for (const SymmetryPlane& p : model_.mesh.symmetry) planes.push_back({p.axis, p.at, 1.0});
      sph::Options o;
      o.alpha = model_.sph.alpha;
      o.beta = model_.sph.beta;
      o.artificial_stress = model_.sph.artificial_stress;
      o.step_factor = model_.sph.step_factor;
      o.faces = model_.sph.faces;
      o.fracture = model_.element.fracture;
      sph_ = std::make_unique<sph::Stage>(o, std::move(planes));
      modules_.push_back("fracture:sph");
    }
    modules_.push_back("response:particles");
  }
  if (!model_.mesh.symmetry.empty()) modules_.push_back("symmetry");
  if (!model_.constraints.empty()) modules_.push_back("boundary_conditions");
  if (!model_.walls.empty()) {
    modules_.push_back("response:rigid_walls");
    surface_nodes_ = all_surface_nodes(state_.surfaces);
    wall_force_max_.assign(model_.walls.size(), 0.0);
  }
  // One broadphase for the detection: between bodies with contact, for particles with them and
  // with each other; for SPH particles, every pair and face within their kernel's reach too (the
  // SPH stage's neighbours).
  if (model_.contact || fragmentation_) {
    CandidateSettings cs =
        model_.contact
            ? candidate_settings(*model_.contact, fragmentation_ != nullptr)
            : CandidateSettings{.broadphase = "sweep", .bodies = false, .particles = true};
    if (sph_) cs.kernel_reach = sph_->options().reach * sph::k_support;
    candidates_ = std::make_unique<ContactCandidates>(model_.mesh, state_.surfaces, cs);
  }
  if (model_.contact) {
    double wave_speed = 0.0;  // the bodies' fastest, for the push speed of contacts
    for (const Material& m : model_.materials) wave_speed = std::max(wave_speed, m.wave_speed());
    contact_ = std::make_unique<ContactDetection>(model_.mesh, state_.surfaces, *model_.contact,
                                                  wave_speed);
    modules_.push_back("broadphase:" + model_.contact->broadphase);
    modules_.push_back("narrowphase:node_face");
    modules_.push_back("response:node_face");
    if (model_.contact->edge_edge) modules_.push_back("narrowphase:edge_edge");
    if (model_.contact->verify) {
      resolver_ = std::make_unique<StepResolver>(model_.mesh, model_.constraints);
      modules_.push_back("contact:verify");
    }
  }
  modules_.push_back("diagnostics:balance");

  // The profile lists the stages this case runs, in pipeline order.
  for (const Named<Stage>& stage : k_stage_names) {
    const Stage s = stage.value;
    if (s == Stage::verify && !resolver_) continue;
    if (s == Stage::broadphase && !candidates_) continue;
    if (s == Stage::narrowphase && !contact_) continue;
    if (s == Stage::response && !corrects()) continue;
    if ((s == Stage::fracture || s == Stage::particles) && !fragmentation_) continue;
    if (s == Stage::sph && !sph_) continue;
    profile_[s] = 0.0;
  }
  if (mpi::ranks() > 1) {
    // Distributed: every process holds the nodes' whole state
    // and runs the whole step, but updates only its own tets in the element stage and receives
    // what the step needs of the others' (element.cpp: nodal forces, damage). Each process
    // cuts the mesh itself: METIS gives the same pieces for the same mesh, ranks and seed.
    try {
      partition_ = partition_mesh(model_.mesh, model_.surfaces, {.ranks = mpi::ranks()});
    } catch (const PartitionError& e) {
      throw RunFailure(std::string("cannot run on ") + std::to_string(mpi::ranks()) +
                       " processes: " + e.what());
    }
    std::vector<std::vector<Index>> rank_tets(static_cast<std::size_t>(mpi::ranks()));
    for (std::size_t t = 0; t < partition_.tet_rank.size(); ++t)
      rank_tets[static_cast<std::size_t>(partition_.tet_rank[t])].push_back(static_cast<Index>(t));
    elements_.distribute(mpi::rank(), std::move(rank_tets));
    modules_.push_back("parallel:mpi_replicated");
  }
  elements_stage();  // F^0 and τ^0; the first step then uses τ_v = τ/2
  st.dt_prev = 0.0;
}

void Simulation::add_observer(Observer* observer, const std::string& module_name) {
  observers_.push_back(observer);
  modules_.push_back(module_name);
}

void Simulation::convert_cells(const std::vector<Index>& tets) {
  if (state_.step != 0 || !fragmentation_)
    throw std::logic_error("convert_cells: before the first step, with fracture.particles");
  fragmentation_->erode(tets);
  fracture_stage();
  elements_stage();
  if (sph_) {
    state_.dt = std::min(
        state_.dt,
        settings_.cfl *
            sph_->forces(state_, candidates_->primitives().faces, sph_candidates()).dt_stable);
  }
}

bool Simulation::done() const {
  return state_.t >= settings_.end_time || released();
}

bool Simulation::released() const {
  return settings_.end_when_released > 0.0 && last_push_ >= 0.0 &&
         state_.t - last_push_ >= settings_.end_when_released;
}

template <class Body>
void Simulation::timed(Stage stage, Body&& body) {
  StageTimer t(profile_[stage]);
  body();
}

// The step, in the order of Dobritsa et al. (2019): the predicted motion (their eqs. 2, 3),
// the corrections of U* by walls and contact before any position moves, then the committed
// update (eq. 1) and the elements' forces for the next step.
void Simulation::step() {
  if (state_.step >= settings_.max_steps) {
    std::ostringstream os;
    os << "max_steps (" << settings_.max_steps << ") reached at t = " << state_.t
       << " s before end_time " << settings_.end_time << " s";
    throw RunFailure(os.str());
  }
  // A step whose motion fails its verification after the further passes is taken again from
  // the prediction with half the step, up to contact.step_cuts times and while halving may help
  // what fails (StepResolver::helped_by_cut); then impact zones take it.
  for (int cut = 0;; ++cut) {
    timed(Stage::predict, [&] { predict_stage(); });  // U*, x* (eqs. 2, 3)
    detect_stage();   // contact points: walls, bodies (broadphase, narrowphase), particles
    respond_stage();  // the sequential passes over them, island by island
    timed(Stage::predict, [&] { hold_constraints(state_, model_.constraints); });
    if (!resolver_ || resolve_stage(cut < model_.contact->step_cuts)) break;  // verified
    cut_step();
  }
  note_push();                                     // end_when_released
  timed(Stage::balance, [&] { sample_stage(); });  // energy, momentum at tⁿ
  timed(Stage::output, [&] { output_stage(); });   // observers see tⁿ
  if (model_.contact_heat && corrects()) timed(Stage::commit, [&] { heat_stage(); });
  timed(Stage::commit, [&] { commit_stage(); });      // Uⁿ⁺¹, xⁿ⁺¹ (eq. 1)
  if (fragmentation_) fracture_stage();               // cells → particles
  timed(Stage::elements, [&] { elements_stage(); });  // σⁿ⁺¹, Fⁿ⁺¹, next τ
  if (sph_) timed(Stage::sph, [&] { sph_stage(); });  // the SPH particles' σⁿ⁺¹, Fⁿ⁺¹, τ
}

// The final time level sampled: nothing is committed after it, so nothing to verify.
void Simulation::finish() {
  ended_by_ = state_.t >= settings_.end_time || !released() ? "end_time" : "released";
  finishing_ = true;
  timed(Stage::predict, [&] { predict_stage(); });
  detect_stage();
  respond_stage();
  timed(Stage::predict, [&] { hold_constraints(state_, model_.constraints); });
  timed(Stage::balance, [&] { sample_stage(); });
  timed(Stage::output, [&] { output_stage(); });
}

bool Simulation::corrects() const {
  return !model_.walls.empty() || contact_ || fragmentation_;
}

// The contact points of the step, from xⁿ and x*: walls; one broadphase update (bodies'
// surfaces and particles); the narrow phases between bodies (node–face, edge–edge) and of the
// particles (a particle centre found inside a body is moved back onto the face it is deepest
// behind).
void Simulation::detect_stage() {
  if (!corrects()) return;
  State& st = state_;
  points_.walls = wall_contact_lists(model_.walls, surface_nodes_, st);
  points_.bodies.clear();
  points_.particles.clear();
  points_.broadphase = CandidateStats{};
  const bool particles = fragmentation_ && st.particle_count() > 0;
  if (candidates_ && (contact_ || particles)) {
    points_.broadphase = candidates_->update(st);
    profile_[Stage::broadphase] += points_.broadphase.seconds;
  }
  if (contact_) {
    points_.bodies = contact_->detect(st, *candidates_, points_.narrowphase);
    profile_[Stage::narrowphase] += points_.narrowphase.narrowphase_seconds;
  }
  if (particles) {
    StageTimer t(profile_[Stage::particles]);
    points_.particles = particle_contact_->detect(model_.mesh, st, *candidates_);
    for (const auto& [p, d] : particle_contact_->moves()) {
      st.x[p] += d;
      st.x_star[p] += d;
      ++contact_totals_.particles_moved_out;
      contact_totals_.particle_move_max = std::max(contact_totals_.particle_move_max, d.norm());
    }
  }
}

// The corrections of U* (Dobritsa et al.: after the prediction, before positions are
// committed): walls, contacts and particle contacts, each correction seeing the velocities the
// ones before it left, repeated in `passes` sequential passes, island by island
// (response/islands.hpp: the same result as one thread going through the lists).
void Simulation::respond_stage() {
  if (!corrects()) return;
  StageTimer timer(profile_[Stage::response]);
  State& st = state_;
  for (Vec3& j : st.wall_impulse) j.setZero();
  for (Vec3& j : st.contact_impulse) j.setZero();
  // The symmetry planes' push on SPH particles came with the prediction's kick (their mirror
  // images' part of the forces): the planes' impulse of the step.
  if (sph_)
    for (std::size_t i = 0; i < sph_->plane_forces().size(); ++i)
      st.sph.plane_impulse[i] = kick_ * sph_->plane_forces()[i];
  const int passes = contact_ ? model_.contact->passes : 1;
  std::vector<ContactList>& lists = points_.lists;
  lists.clear();
  for (auto& list : points_.walls) lists.push_back({&list, &st.wall_impulse});
  lists.push_back({&points_.bodies, &st.contact_impulse});
  lists.push_back({&points_.particles, &st.contact_impulse});
  const Islands islands = contact_islands(lists, st.x.size(), points_.island_slot);
  correct_in_islands(lists, islands, passes, st);
  contact_totals_.islands += static_cast<long>(islands.count());
  contact_totals_.island_points += static_cast<long>(islands.refs.size());
  contact_totals_.largest_island_points += static_cast<long>(islands.largest());
  for (const ContactPoint& c : points_.particles)
    contact_totals_.particle_contacts += c.lambda > 0.0;
  wall_results_ = wall_results(points_.walls);
}

// Whether the step's corrections pushed: a wall that is not a symmetry plane, or a contact
// between bodies or particles (the passes, rescue points and impact zones alike: all of them
// land in contact_impulse) exchanged momentum. Every rank alike: the corrections are whole on
// each.
void Simulation::note_push() {
  if (!corrects()) return;
  bool pushed = std::any_of(state_.contact_impulse.begin(), state_.contact_impulse.end(),
                            [](const Vec3& j) { return !j.isZero(0.0); });
  for (std::size_t w = 0; w < model_.walls.size() && !pushed; ++w)
    pushed = !model_.walls[w].mirror &&
             std::any_of(points_.walls[w].begin(), points_.walls[w].end(),
                         [](const ContactPoint& c) { return c.lambda > 0.0; });
  if (pushed) last_push_ = state_.t;
}

// The step's motion verified, and failures resolved (solver/resolve.hpp); false when they are
// left to the step taken again shorter.
bool Simulation::resolve_stage(bool may_cut) {
  StageTimer timer(profile_[Stage::verify]);
  return resolver_->resolve(state_, points_, *candidates_, *contact_, model_.contact->passes,
                            may_cut, contact_totals_);
}

// The step taken again with half its τ: the prediction, detection and passes start over from
// Uⁿ⁻¹ᐟ², xⁿ and Fⁿ, which none of them changed (the passes and the resolver change U* and the
// impulses, which the prediction and the passes set anew; particles the detection moved out of
// a body stay out). Halving quarters what the passes' linearization of a pair's constraint
// misses over the step (second order in the motion).
void Simulation::cut_step() {
  state_.dt *= 0.5;
  if (contact_) contact_->retake_step();
  ContactLedger& ct = contact_totals_;
  ++ct.step_cuts;
  ct.cut_step_min = ct.cut_step_min > 0.0 ? std::min(ct.cut_step_min, state_.dt) : state_.dt;
}

void Simulation::predict_stage() {
  kick_ = 0.5 * (state_.dt_prev + state_.dt);  // predict's τ_v
  predict(state_, model_.constraints);
}

double Simulation::balance_error(const Sample& s) const {
  if (energy_scale_ <= 0.0) return 0.0;
  return std::abs(s.total - s.external_work() - s.contact.work - s.contact_heat - first_.total) /
         energy_scale_;
}

// Distributed: each rank's exact sums over its own tets, merged (exactly: the same bits as one
// process's sum over all tets).
TetSums Simulation::tet_sums_over_ranks() const {
  TetSums sums;
  for (const TetSums& part : mpi::all_gather_value(tet_sums(state_, rank_tets()))) {
    sums.internal.merge(part.internal);
    sums.plastic_work.merge(part.plastic_work);
    sums.viscous_work.merge(part.viscous_work);
  }
  return sums;
}

void Simulation::sample_stage() {
  std::optional<TetSums> sums;
  if (rank_tets()) sums = tet_sums_over_ranks();
  Sample s = sample_balance(state_, have_sample_ ? &last_ : nullptr, sums ? &*sums : nullptr);
  // The kinetic energy holds the fraction f of the coming kick's work; the SPH pairs' heat of
  // that kick goes into the particles' energies at their next update: its part f τ_v Σ q̇ is
  // counted here, beside the work it comes from.
  if (sph_ && state_.sph.size() > 0) {
    const double pending = kick_fraction(state_) * kick_ * sph_->heat_rate();
    s.internal += pending;
    s.total += pending;
  }
  s.final = finishing_;
  s.contact_heat = contact_heat_;
  if (!std::isfinite(s.kinetic) || !std::isfinite(s.momentum.sum())) {
    std::ostringstream os;
    os << "non-finite velocity at t = " << state_.t << " s (step " << state_.step << ")";
    throw RunFailure(os.str());
  }
  for (std::size_t w = 0; w < wall_results_.size(); ++w) {
    // Reaction on the wall: the impulse it gave, along its normal, per unit time.
    const double force = wall_results_[w].impulse.dot(model_.walls[w].normal) / state_.dt;
    s.wall_force.push_back(force);
    wall_force_max_[w] = std::max(wall_force_max_[w], force);
  }
  if (contact_) {
    double lambda = 0.0;
    for (const ContactPoint& c : points_.bodies) lambda += c.lambda;
    s.contact_force = lambda / state_.dt;
    const ContactStepStats& narrow = points_.narrowphase;
    s.contacts = narrow.contacts;
    ContactLedger& ct = contact_totals_;
    ct.node_face += narrow.contacts;
    ct.edge_edge += narrow.edge_contacts;
    ct.edge_candidates += narrow.edge_candidates;
    ct.candidates += narrow.candidates;
    ct.max_per_step = std::max(ct.max_per_step, narrow.contacts);
    ct.normal_impulse += lambda;
    ct.broadphase_build += points_.broadphase.build_seconds;
    ct.rebuilds += points_.broadphase.rebuilt;
    ct.broadphase_query += points_.broadphase.query_seconds;
    if (lambda > 0.0) {
      if (ct.first_time < 0.0) ct.first_time = state_.t;
      ct.last_time = state_.t;
      ++ct.steps_in_contact;
      ct.max_force = std::max(ct.max_force, s.contact_force);
    }
  }
  if (!have_sample_) first_ = s;
  have_sample_ = true;
  energy_scale_ = std::max(
      {energy_scale_, std::abs(first_.total), std::abs(s.external_work()), s.kinetic + s.internal});
  s.balance_error = balance_error(s);
  balance_error_max_ = std::max(balance_error_max_, s.balance_error);
  last_ = s;
}

double Simulation::contact_separation() const {
  return contact_ ? contact_->separation() : 0.0;
}

RunFigures Simulation::run_figures() const {
  RunFigures r;
  r.contact_first_time = contact_totals_.first_time;
  r.contact_last_time = contact_totals_.last_time;
  r.contact_max_force = contact_totals_.max_force;
  r.contact_impulse = contact_totals_.normal_impulse;
  for (const BodyStats& b : body_stats(model_, state_)) r.body_velocity.push_back(b.velocity);
  return r;
}

// Observers see the nodes whole; in a distributed run a tet's fields are current only on the
// rank that owns it (every tet's damage on all), so an observer reads its own tets
// (OutputWriter writes its piece) and the sample's sums.
void Simulation::output_stage() {
  for (Observer* o : observers_) o->observe(state_, last_);
}

void Simulation::gather_state() {
  elements_.share_whole_state(state_);
}

void Simulation::commit_stage() {
  commit(state_);
  // Translated and frozen impact zones take the positions the zones set (their velocities
  // are the zone's rigid ones).
  if (resolver_)
    for (const auto& [node, x] : resolver_->fixed_positions()) state_.x[node] = x;
}

// The kinetic energy the step's exchanges between bodies and particles dissipated, as internal
// energy of the cells and particles at their nodes (response/heat.hpp: per island, the contact
// work the balance books), before cells become particles and the elements' pass sees it; after
// the sample, so that the balance of tⁿ⁺¹ counts it. The islands anew: the verification may
// have added rescue points.
void Simulation::heat_stage() {
  State& st = state_;
  const Islands islands = contact_islands(points_.lists, st.x.size(), points_.island_slot);
  node_heat_.assign(st.x.size(), 0.0);
  std::vector<char> heats(points_.lists.size(), 1);  // the walls' lists first
  for (std::size_t w = 0; w < model_.walls.size(); ++w) heats[w] = model_.walls[w].mirror;
  node_heat(points_.lists, heats, node_planes_, islands, st, node_heat_);
  contact_heat_ += deposit_heat(model_.mesh.tets, model_.materials, node_heat_, st);
}

// Destroyed boundary cells of the last element pass become particles before this one, which
// then no longer sees them; the surfaces they exposed join the contact search at once. The
// model stays as set up: the surfaces of the run are the state's (State::surfaces), and the contact
// modules keep their memory across the change.
// Timed by itself: the detection's lists updated count in the broadphase stage.
void Simulation::fracture_stage() {
  {
    StageTimer t(profile_[Stage::fracture]);
    if (fragmentation_->convert(model_.mesh, model_.materials, state_) == 0) return;
    fragmentation_->update(model_.mesh, state_.surfaces);
  }
  std::vector<Index> renamed;
  timed(Stage::broadphase,
        [&] { renamed = candidates_->surfaces_changed(state_.surfaces, state_); });
  StageTimer t(profile_[Stage::fracture]);
  if (!model_.walls.empty()) surface_nodes_ = all_surface_nodes(state_.surfaces);
  if (contact_) contact_->edges_renamed(renamed);
  if (resolver_) resolver_->surfaces_changed();
}

// Erosion's limits, set at the first step: a cell erodes when its stable step falls below
// erosion_step_ratio times the first step, the whole model's (`first`, its smallest cell's) or
// its own body's (fracture.erosion_reference: body).
void Simulation::set_erosion_limits(double first) {
  const Mesh& mesh = model_.mesh;
  std::vector<double> steps(mesh.bodies.size(), first);
  if (model_.erosion_per_body)
    steps = body_stable_steps(mesh.tets, mesh.tet_body, mesh.bodies.size(), model_.element, state_);
  std::vector<double> dt2;
  for (double s : steps) dt2.push_back(std::pow(model_.erosion_step_ratio * s, 2));
  elements_.set_erosion_limits(std::move(dt2), mesh.tet_body);
}

std::vector<double> Simulation::erosion_steps() const {
  std::vector<double> steps;
  for (double dt2 : elements_.erosion_limits()) steps.push_back(std::sqrt(dt2));
  return steps;
}

void Simulation::elements_stage() {
  State& st = state_;
  try {
    const ForceResult r = st.step > 0
                              ? elements_.update(model_.mesh.tets, model_.materials, st.dt_prev, st)
                              : elements_.forces(model_.mesh.tets, st);
    critical_tet_ = r.critical_tet;
    if (fragmentation_) {  // erosion: by the step, and by the plastic strain (per material)
      if (st.step == 0 && model_.erosion_step_ratio > 0.0) set_erosion_limits(r.dt_stable);
      fragmentation_->erode(r.eroding);
    }
    // No step is shortened to land on end_time: an abrupt change of τ costs the leapfrog
    // its exact energy balance (see sample_balance), so the run ends at the first step at or
    // after end_time and reports the time reached.
    st.dt = settings_.cfl * r.dt_stable;
    min_dt_ = std::min(min_dt_, st.dt);
    // No cell left (a body made of particles): the particles' stage sets the step.
    if (!(st.dt > 0.0) || (!std::isfinite(st.dt) && st.sph.size() == 0)) {
      std::ostringstream os;
      os << "time step " << st.dt << " s is not positive and finite";
      throw RunFailure(os.str());
    }
    watch_step();
  } catch (const InvertedElement& e) {
    rethrow_with_body(e);
  }
}

// The SPH particles' candidate pairs and faces: the detection's lists at the committed
// positions (found anew there when they no longer hold; the search is counted as the
// broadphase's).
sph::Candidates Simulation::sph_candidates() {
  bool searched = false;
  const CandidateLists& lists = candidates_->particles_at(state_, &searched);
  contact_totals_.rebuilds += searched;
  return {lists.edge_edge, lists.node_face};
}

// The SPH particles (fracture.debris: sph): their material over the step just committed, from
// U^{n+1/2}, the pair heat of the last forces over the prediction's τ_v; their forces at x^{n+1}
// into the particles' nodes; the next step no longer than their stable step allows.
void Simulation::sph_stage() {
  State& st = state_;
  if (st.sph.size() == 0) return;
  const std::vector<Face>& faces = candidates_->primitives().faces;
  const sph::Candidates candidates = sph_candidates();
  sph_->update(model_.materials, st.dt_prev, kick_, st, faces, candidates);
  const sph::StepLimit limit = sph_->forces(st, faces, candidates);
  const double dt = settings_.cfl * limit.dt_stable;
  particle_min_dt_ = std::min(particle_min_dt_, dt);
  if (dt < st.dt) {
    st.dt = dt;
    min_dt_ = std::min(min_dt_, dt);
    ++particle_limited_steps_;
    watch_particle_step(limit.critical);
  }
  if (!(st.dt > 0.0) || !std::isfinite(st.dt)) {
    std::ostringstream os;
    os << "time step " << st.dt << " s of the SPH particles is not positive and finite";
    throw RunFailure(os.str());
  }
}

// A step that falls by a decade below the first is reported with the tet that sets it. In a
// distributed run the tet's fields are current on its rank only: that rank sends them (every
// rank meets the same fall at the same step, so the broadcast is collective).
void Simulation::watch_step() {
  const State& st = state_;
  if (first_dt_ == 0.0) {
    first_dt_ = st.dt;
    return;
  }
  if (!(st.dt < first_dt_ / collapse_factor_) || critical_tet_ < 0) return;
  while (st.dt < first_dt_ / collapse_factor_) collapse_factor_ *= 10.0;
  const Index t = critical_tet_;
  std::array<double, 4> fields{st.vol[t] / st.vol0[t], st.p[t], st.eps_p[t],
                               static_cast<double>(st.damage[t])};
  if (elements_.rank_tets()) {
    std::string bytes(sizeof(fields), '\0');
    std::memcpy(bytes.data(), fields.data(), sizeof(fields));
    bytes = mpi::broadcast(bytes, partition_.tet_rank[t]);
    std::memcpy(fields.data(), bytes.data(), sizeof(fields));
  }
  Vec3 centroid = Vec3::Zero();
  for (const Index k : model_.mesh.tets[t]) centroid += 0.25 * st.x[k];
  record_fall(t, -1, centroid, fields);
}

// A fall of the step that an SPH particle sets (particles are whole on every rank).
void Simulation::watch_particle_step(Index p) {
  const State& st = state_;
  if (p < 0 || first_dt_ == 0.0 || !(st.dt < first_dt_ / collapse_factor_)) return;
  while (st.dt < first_dt_ / collapse_factor_) collapse_factor_ *= 10.0;
  const Index fp = st.first_particle;
  record_fall(st.particle_tet[p], p, st.x[fp + p],
              {st.sph.vol[p] / st.sph.vol0[p], st.sph.p[p], st.sph.eps_p[p],
               static_cast<double>(st.sph.damage[p])});
}

// A fall's record: when, what sets the step (a tet, or an SPH particle and the tet it was made
// of), where (the tet's centroid, the particle's centre) and its state: V/V0, p, plastic
// strain, damage.
void Simulation::record_fall(Index tet, Index particle, const Vec3& position,
                             const std::array<double, 4>& fields) {
  const State& st = state_;
  StepCollapse c;
  c.step = st.step;
  c.t = st.t;
  c.dt = st.dt;
  c.first_dt = first_dt_;
  c.tet = tet;
  c.particle = particle;
  if (tet >= 0) {
    const BodyRange& b = model_.mesh.bodies[model_.mesh.tet_body[tet]];
    c.body = b.name;
    c.body_tet = tet - b.tet_begin;
  }
  c.position = position;
  c.volume_ratio = fields[0];
  c.pressure = fields[1];
  c.plastic_strain = fields[2];
  c.damage = static_cast<int>(fields[3]);
  c.steps_to_end = (settings_.end_time - st.t) / st.dt;
  step_collapses_.push_back(c);
}

void persist(Archive& ar, StepCollapse& c) {
  ar(c.step, c.t, c.dt, c.first_dt, c.tet, c.particle, c.body, c.body_tet, c.position,
     c.volume_ratio, c.pressure, c.plastic_strain, c.damage, c.steps_to_end);
}

void Simulation::persist(Archive& ar) {
  ar.section("simulation");
  std::size_t nodes = model_.mesh.x.size(), tets = model_.mesh.tets.size();
  ar(nodes, tets);
  if (nodes != model_.mesh.x.size() || tets != model_.mesh.tets.size())
    throw ArchiveError("the mesh has another number of nodes or tets");
  // The mesh itself (a mesh file the case names is not in the inputs' hash): its nodes, tets
  // and bodies, bit for bit.
  Fnv1a f;
  const Mesh& mesh = model_.mesh;
  f.add(reinterpret_cast<const char*>(mesh.x.data()), mesh.x.size() * sizeof(Vec3));
  f.add(reinterpret_cast<const char*>(mesh.tets.data()), mesh.tets.size() * sizeof(Tet));
  f.add(reinterpret_cast<const char*>(mesh.tet_body.data()),
        mesh.tet_body.size() * sizeof(mesh.tet_body[0]));
  std::uint64_t mesh_hash = f.h;
  ar(mesh_hash);
  if (mesh_hash != f.h)
    throw ArchiveError(
        "written on another mesh (the same numbers of nodes and tets, other "
        "positions or cells: a mesh file changed since)");
  ar(state_);
  std::vector<double> erosion = elements_.erosion_limits();
  ar(erosion);
  if (ar.loading()) elements_.set_erosion_limits(std::move(erosion), model_.mesh.tet_body);
  if (candidates_) candidates_->persist(ar, state_.surfaces);
  if (contact_) contact_->persist(ar);
  if (fragmentation_) fragmentation_->persist(ar);
  if (sph_) sph_->persist(ar);
  ar.section("ledgers");
  ar(kick_, contact_totals_, contact_heat_, wall_force_max_, first_, last_, have_sample_,
     last_push_, energy_scale_, balance_error_max_, critical_tet_, min_dt_, particle_limited_steps_,
     particle_min_dt_, first_dt_, collapse_factor_, step_collapses_, profile_);
  if (ar.loading()) {
    if (!model_.walls.empty()) surface_nodes_ = all_surface_nodes(state_.surfaces);
    if (resolver_) resolver_->surfaces_changed();
  }
}

std::string StepCollapse::message() const {
  static const char* const damage_names[] = {"intact", "damaged", "destroyed", "a particle"};
  std::ostringstream os;
  os.precision(3);
  os << "the time step fell to " << dt << " s, " << first_dt / dt << "x below the first ("
     << first_dt << " s), at t = " << t << " s (step " << step << "): set by ";
  if (particle >= 0)
    os << "SPH particle " << particle << " (made of body '" << body << "', tet " << body_tet << ")";
  else
    os << "body '" << body << "', tet " << body_tet;
  os << " at (" << position.x() << ", " << position.y() << ", " << position.z()
     << ") m, V/V0 = " << volume_ratio << ", p = " << pressure << " Pa, plastic strain "
     << plastic_strain << ", " << damage_names[std::clamp(damage, 0, 3)] << "; at this step size "
     << std::fixed << std::setprecision(0) << steps_to_end
     << " more steps would reach end_time (the step may recover or fall further: not a "
        "forecast)";
  return os.str();
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
