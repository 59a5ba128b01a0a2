// One explicit run: the step composed from the stages the case needs.
#pragma once

#include <array>
#include <chrono>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "tetcontact/diagnostics/balance.hpp"
#include "tetcontact/diagnostics/reference.hpp"
#include "tetcontact/element/element.hpp"
#include "tetcontact/fracture/particles.hpp"
#include "tetcontact/mesh/partition.hpp"
#include "tetcontact/model/ledger.hpp"
#include "tetcontact/model/model.hpp"
#include "tetcontact/model/sample.hpp"
#include "tetcontact/model/state.hpp"
#include "tetcontact/narrowphase/contact.hpp"
#include "tetcontact/narrowphase/particle_contact.hpp"
#include "tetcontact/response/wall.hpp"
#include "tetcontact/solver/resolve.hpp"
#include "tetcontact/sph/sph.hpp"

namespace tc {

/// The stable step fallen below a tenth, a hundredth, ... of the first (once per decade): the
/// tet that sets it, where it is and its state, so that a run which would crawl says why early.
struct StepCollapse {
  long step = 0;
  double t = 0.0, dt = 0.0, first_dt = 0.0;
  Index tet = -1;       // global (a particle's: the cell it was made of)
  Index particle = -1;  // the SPH particle that sets the step, if one does
  std::string body;
  Index body_tet = -1;           // within its body
  Vec3 position = Vec3::Zero();  // the tet's centroid now (a particle's centre)
  double volume_ratio = 0.0, pressure = 0.0, plastic_strain = 0.0;
  int damage = 0;
  double steps_to_end = 0.0;  // at this step, to end_time
  /// One line for the user.
  std::string message() const;
};

/// The state at t = 0: reference positions, initial velocities, lumped masses (a quarter of
/// each tet's mass on each of its nodes), zero stress, sound speeds.
State initial_state(const Model& model);

class Simulation {
 public:
  Simulation(Model model, SolverSettings settings);
  // The stages hold references into the model and the state: a Simulation stays where it is.
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// One step t^n → t^{n+1}.
  void step();
  /// Samples the final time level (prediction only, nothing committed) so that observers see
  /// it. Call once, after the last step. The run ends at the first step at or after end_time,
  /// or once released (SolverSettings::end_when_released).
  void finish();
  bool done() const;
  /// No wall (symmetry planes aside) and no contact has pushed for end_when_released since
  /// the last push (never before the first push, never without end_when_released).
  bool released() const;
  /// Why the run ended, once finished: "end_time" or "released".
  const std::string& ended_by() const { return ended_by_; }
  /// The time level of the last step a wall (symmetry planes aside) or a contact pushed on a
  /// body or particle, s; < 0: none did.
  double last_push() const { return last_push_; }

  void add_observer(Observer* observer, const std::string& module_name);
  /// Before the first step: turns the cells `tets` into particles as erosion does (their mass,
  /// momentum, state), and sets the forces and the step anew. For checks of the particles'
  /// coupling to the cells around them. Throws std::logic_error after the first step or
  /// without fracture.particles.
  void convert_cells(const std::vector<Index>& tets);
  /// Names a stage run outside the step (listed in `modules`).
  void add_module(const std::string& name) { modules_.push_back(name); }

  const State& state() const { return state_; }
  const Model& model() const { return model_; }
  const SolverSettings& settings() const { return settings_; }
  const Sample& first_sample() const { return first_; }
  const Sample& last_sample() const { return last_; }
  /// |kinetic + internal − external work − initial total| / energy scale, max over the run;
  /// the scale is the largest of |initial total|, |external work| and kinetic + internal seen.
  double balance_error_max() const { return balance_error_max_; }
  double balance_error(const Sample& s) const;
  /// Largest normal reaction force seen on each wall, N.
  const std::vector<double>& wall_force_max() const { return wall_force_max_; }

  /// The figures of the run that references measure (diagnostics/reference).
  RunFigures run_figures() const;
  const ContactLedger& contact_totals() const { return contact_totals_; }
  /// The separation contacts aim at beyond rounding (m; 0 without contact).
  double contact_separation() const;
  bool has_contact() const { return contact_ != nullptr; }
  const std::vector<std::string>& modules() const { return modules_; }
  /// The conversions of destroyed cells into particles (null when the case has none).
  const ConversionLedger* conversions() const {
    return fragmentation_ ? &fragmentation_->ledger() : nullptr;
  }
  const StepProfile& profile() const { return profile_; }
  Index critical_tet() const { return critical_tet_; }
  /// The SPH particles' neighbour lists of the last step (fracture.debris: sph), else null.
  const sph::Neighbours* sph_neighbours() const { return sph_ ? &sph_->neighbours() : nullptr; }
  /// The (particle or image, face) pairs within reach at the last step (0 without SPH).
  std::size_t sph_face_pairs() const { return sph_ ? sph_->face_pairs() : 0; }
  /// The smallest time step of the run, s.
  double min_dt() const { return min_dt_; }
  /// The steps whose length the SPH particles set (their stable step below the tets'), and
  /// the particles' smallest step (infinite without particles).
  long particle_limited_steps() const { return particle_limited_steps_; }
  double particle_min_dt() const { return particle_min_dt_; }
  /// The step after the first element pass, s.
  double first_dt() const { return first_dt_; }
  /// Per body, the stable step below which its cells erode (fracture.erosion_step_ratio of
  /// the first step, the model's or the body's); empty without erosion by the step.
  std::vector<double> erosion_steps() const;
  /// The falls of the step to a tenth of the first, a hundredth, ... (StepCollapse).
  const std::vector<StepCollapse>& step_collapses() const { return step_collapses_; }
  /// The decomposition of a distributed run (ranks = 1 on one process): each rank
  /// updates the tets METIS gave it.
  const Partition& partition() const { return partition_; }
  /// The last step's contact points with their accumulated impulses (the tests' view of what
  /// the passes solved).
  const StepContacts& contact_points() const { return points_; }
  /// Distributed: gathers every tet's fields on every rank (collective; the run's end, before
  /// the summary and references read them). Nothing on one process.
  void gather_state();
  /// What a checkpoint holds of the run (model/archive.hpp), between two steps: the state, what
  /// each stage keeps from one step to the next (the candidate lists and where they were found,
  /// the edge pairs in contact, the converted cells, the SPH particles' last forces, the erosion
  /// limit) and the run's ledgers and samples. Read back into a Simulation set up from the same
  /// model, the steps that follow are those of the run that wrote it, bit for bit. Distributed:
  /// written after gather_state() (every tet's fields), read back on any number of ranks.
  void persist(Archive& ar);
  /// Distributed: this rank's tets (ascending); null on one process.
  const std::vector<Index>* rank_tets() const { return elements_.rank_tets(); }

 private:
  void predict_stage();

  void sample_stage();
  TetSums tet_sums_over_ranks() const;
  void output_stage();
  void commit_stage();
  void sph_stage();
  sph::Candidates sph_candidates();
  void elements_stage();
  void set_erosion_limits(double first);
  void fracture_stage();
  void heat_stage();
  bool corrects() const;  // walls, contact or particles: the step corrects U*
  void detect_stage();
  void respond_stage();
  bool resolve_stage(bool may_cut);
  void cut_step();
  void note_push();  // last_push_
  template <class Body>
  void timed(Stage stage, Body&& body);
  [[noreturn]] void rethrow_with_body(const InvertedElement& e) const;
  void watch_step();                         // step_collapses_
  void watch_particle_step(Index particle);  // the same, where an SPH particle sets the step
  void record_fall(Index tet, Index particle, const Vec3& position,
                   const std::array<double, 4>& fields);

  const Model model_;  // as set up: never changed during the run
  SolverSettings settings_;
  State state_;
  ElementStage elements_;
  std::vector<Index> surface_nodes_;
  std::vector<WallResult> wall_results_;
  std::unique_ptr<ContactCandidates> candidates_;  // detection's broadphase: bodies, particles
  std::unique_ptr<ContactDetection> contact_;
  std::unique_ptr<Fragmentation> fragmentation_;
  std::unique_ptr<ParticleContact> particle_contact_;
  std::unique_ptr<sph::Stage> sph_;         // with fracture.debris: sph
  double kick_ = 0.0;                       // τ_v of the step's prediction (the SPH pair heat's)
  std::unique_ptr<StepResolver> resolver_;  // with contact.verify
  StepContacts points_;                     // this step's contact points
  ContactLedger contact_totals_;
  std::vector<double> node_heat_;          // this step's contact heat per node (heat_stage)
  std::vector<std::uint8_t> node_planes_;  // symmetry planes each mesh node lies on
  double contact_heat_ = 0.0;              // deposited so far, J
  std::vector<double> wall_force_max_;
  Sample first_, last_;
  bool have_sample_ = false;
  bool finishing_ = false;  // finish(): its sample is the run's last
  double last_push_ = -1.0;
  std::string ended_by_;
  double energy_scale_ = 0.0;
  double balance_error_max_ = 0.0;
  Index critical_tet_ = -1;
  double min_dt_ = std::numeric_limits<double>::infinity();
  long particle_limited_steps_ = 0;
  double particle_min_dt_ = std::numeric_limits<double>::infinity();
  double first_dt_ = 0.0;          // the step after the first element pass
  double collapse_factor_ = 10.0;  // the next fall reported: below first_dt_ / this
  std::vector<StepCollapse> step_collapses_;
  std::vector<std::string> modules_;
  std::vector<Observer*> observers_;
  StepProfile profile_;
  Partition partition_;
};

}  // namespace tc
