#include "tetcontact/app/run.hpp"

#include <unistd.h>

#include <csignal>
#include <cstdlib>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>

#include "tetcontact/app/partition.hpp"
#include "tetcontact/app/runs.hpp"
#include "tetcontact/app/setup.hpp"
#include "tetcontact/app/summary.hpp"
#include "tetcontact/diagnostics/expect.hpp"
#include "tetcontact/diagnostics/reference.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/io/checkpoint.hpp"
#include "tetcontact/io/files.hpp"
#include "tetcontact/io/json.hpp"
#include "tetcontact/io/output.hpp"
#include "tetcontact/mesh/gmsh.hpp"
#include "tetcontact/model/archive.hpp"
#include "tetcontact/parallel/mpi.hpp"
#include "tetcontact/parallel/parallel.hpp"
#include "tetcontact/solver/run_loop.hpp"
#include "tetcontact/solver/simulation.hpp"

namespace tc {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Progress on stderr: a bar redrawn in place on a terminal, a line every 10% otherwise.
class Progress {
 public:
  Progress(bool quiet, double end_time)
      : quiet_(quiet), tty_(isatty(STDERR_FILENO)), end_(end_time), start_(Clock::now()) {}
  void update(const State& st) {
    if (quiet_) return;
    const double wall = seconds_since(start_);
    if (wall - last_ < (tty_ ? 0.2 : 5.0) && !(tty_ ? false : st.t >= next_mark_)) return;
    last_ = wall;
    const double frac = std::min(1.0, st.t / end_);
    const double rate = st.step / std::max(wall, 1e-9);
    const double eta = frac > 0 ? wall * (1.0 - frac) / frac : 0.0;
    if (tty_) {
      const int width = 30, filled = static_cast<int>(frac * width);
      std::fprintf(stderr, "\r[%s%s] %5.1f%%  t = %.3e s  %.0f steps/s  ETA %.0f s ",
                   std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(),
                   100 * frac, st.t, rate, eta);
    } else {
      std::fprintf(stderr, "progress: %5.1f%%  t = %.3e s  step %ld  %.0f steps/s  ETA %.0f s\n",
                   100 * frac, st.t, st.step, rate, eta);
      while (next_mark_ <= st.t) next_mark_ += 0.1 * end_;
    }
  }
  void done() {
    if (!quiet_ && tty_) std::fprintf(stderr, "\r%80s\r", "");
  }

 private:
  bool quiet_, tty_;
  double end_;
  Clock::time_point start_;
  double last_ = -1e300, next_mark_ = 0.0;
};

// Reads the case and builds the model; any bad input becomes one line on stderr and exit 2.
template <class F>
int with_bad_input_guard(F&& body) {
  try {
    return body();
  } catch (const CaseError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
  } catch (const SetupError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
  } catch (const OutputError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
  } catch (const GaugeError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
  } catch (const CheckpointError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
  }
  return 2;
}

// What a run leaves for its report: the folder, the loop's status and exit code, its wall time
// and the largest time a rank spent in collectives, the warnings said, the references.
struct RunRecord {
  std::string dir, status;
  int code = 0;
  double wall = 0.0, communication = 0.0;
  std::vector<std::string> warnings;
  ReferenceRecorder* references = nullptr;
  GaugeWriter* gauges = nullptr;
  std::vector<std::pair<long, double>> restarts;  // the checkpoints it went on from
};

// The case's gauges placed on the model (GaugeError naming a gauge no cell holds, with the case
// file), before anything is written.
void check_gauges(const Case& c, const Model& model) {
  if (c.output.gauges.empty()) return;
  try {
    Gauges placed(model.mesh, c.output.gauges);
  } catch (const GaugeError& e) {
    throw GaugeError(c.file + ": gauges: " + e.what());
  }
}

int report_run(const RunOptions& o, const Case& c, const Simulation& sim, OutputWriter& writer,
               RunRecord run);

// The hash of a run's complete inputs (runs.hpp's run_key): what a checkpoint must have been
// written for. The threads and the checkpoints' own settings change no result: a run may go on
// with others.
std::string inputs_hash(const RunOptions& o, const Case& c) {
  std::vector<std::string> overrides;
  for (const std::string& s : o.overrides)
    if (s.rfind("solver.threads=", 0) != 0 && s.rfind("output.checkpoint", 0) != 0)
      overrides.push_back(s);
  const std::string key = run_key(o.case_path, overrides, c.material_library);
  Fnv1a f;
  f.add(key.data(), key.size());
  return f.hex();
}

// When a run's checkpoints are due (output.checkpoint): every `steps` steps, or at the first
// step at or after each multiple of `interval`.
class CheckpointClock {
 public:
  explicit CheckpointClock(const OutputSpec& spec)
      : interval_(spec.checkpoint_interval), steps_(spec.checkpoint_steps) {}
  bool on() const { return interval_ > 0.0 || steps_ > 0; }
  bool due(const State& st) const {
    if (steps_ > 0) return st.step % steps_ == 0;
    return interval_ > 0.0 && st.t >= next_ - 1e-9 * interval_;
  }
  // Past the checkpoint at t (and, restarted, past every one before t).
  void passed(double t) {
    if (interval_ > 0.0)
      while (next_ <= t + 1e-9 * interval_) next_ += interval_;
  }

 private:
  double interval_;
  long steps_;
  double next_ = 0.0;
};

// Fault injection for the restart tests: TETCONTACT_KILL_AT_STEP=N sends the process a signal
// right after step N: SIGKILL (as an out-of-memory killer would), or the signal number
// TETCONTACT_KILL_SIGNAL gives (15: a batch queue's SIGTERM).
long kill_at_step() {
  const char* s = std::getenv("TETCONTACT_KILL_AT_STEP");
  return s ? std::atol(s) : -1;
}
int kill_signal() {
  const char* s = std::getenv("TETCONTACT_KILL_SIGNAL");
  return s ? std::atoi(s) : SIGKILL;
}

// SIGTERM or SIGINT (a batch queue's notice before its limit, Ctrl-C) in a run with checkpoints:
// the step under way ends, a checkpoint of it is written, and the run stops there.
// A second signal while the step ends acts as it would without checkpoints.
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void note_stop_signal(int signal) {
  if (g_stop_signal != 0) {
    std::signal(signal, SIG_DFL);
    std::raise(signal);
  }
  g_stop_signal = signal;
}

}  // namespace

int check_case(const RunOptions& o) {
  return with_bad_input_guard([&] {
    const Case c = load_case(o.case_path, o.overrides);
    std::vector<std::string> notes;
    Model model = build_model(c, &notes);
    for (const std::string& n : notes) std::cerr << "tetcontact: note: " << n << "\n";
    const std::size_t nodes = model.mesh.x.size(), tets = model.mesh.tets.size();
    std::vector<std::string> names;
    for (const BodyRange& b : model.mesh.bodies) names.push_back(b.name);
    try {
      for (const std::string& w : mach_warnings(c, model))
        std::cerr << "tetcontact: warning: " << w << "\n";
      for (const std::string& n : shield_notes(c)) std::cerr << "tetcontact: note: " << n << "\n";
      check_gauges(c, model);
      Simulation sim(std::move(model), solver_settings(c));
      std::cout << c.file << ": ok — case '" << c.name << "', " << names.size() << " bodies, "
                << nodes << " nodes, " << tets << " tets; first time step " << fmt(sim.state().dt)
                << " s: " << fmt(std::ceil(c.end_time / sim.state().dt), "%.0f") << " steps to "
                << fmt(c.end_time)
                << " s if the step kept that size (an impact shrinks it: expect more)\n";
    } catch (const RunFailure& e) {
      throw SetupError(c.file + ": " + e.what());
    }
    return 0;
  });
}

int run_case(const RunOptions& o) {
  const bool root = mpi::rank() == 0;
  Case c;
  std::unique_ptr<Simulation> sim;
  std::string dir;
  std::vector<std::string> warnings;
  Checkpoint restart;  // --restart: the checkpoint to go on from
  const int setup = with_bad_input_guard([&] {
    c = load_case(o.case_path, o.overrides);
    std::vector<std::string> notes;
    Model model = build_model(c, &notes);
    // Notes, warnings and regime statements go to stderr even under --quiet (which silences
    // only the progress and the table): a batch of runs keeps them in its logs.
    if (root)
      for (const std::string& n : notes) std::cerr << "tetcontact: note: " << n << "\n";
    try {
      sim = std::make_unique<Simulation>(std::move(model), solver_settings(c));
    } catch (const RunFailure& e) {  // an element inverted in the initial geometry
      throw SetupError(c.file + ": " + e.what());
    }
    check_gauges(c, sim->model());
    warnings = mach_warnings(c, sim->model());
    if (root) {
      for (const std::string& w : warnings) std::cerr << "tetcontact: warning: " << w << "\n";
      for (const std::string& n : regime_notes(c, sim->model()))
        std::cerr << "tetcontact: regime: " << n << "\n";
      for (const std::string& n : shield_notes(c)) std::cerr << "tetcontact: note: " << n << "\n";
    }
    if (!o.restart.empty()) {
      // The run goes on in its own folder, from its newest checkpoint (refused when another
      // build or other inputs wrote it), and nothing is written unless that checkpoint holds.
      if (!o.out_dir.empty() || o.force)
        throw OutputError("--restart goes on in the run's own folder: leave out --out and --force");
      dir = restart_run_folder(o.restart);
      if (std::filesystem::exists(dir + "/summary.json"))
        throw OutputError(dir + ": the run there has ended (summary.json): nothing to restart");
      std::vector<std::string> skipped;  // damaged newer ones
      restart = read_checkpoint(o.restart, program_identity(), inputs_hash(o, c), &skipped);
      if (root)
        for (const std::string& s : skipped)
          std::cerr << "tetcontact: warning: " << s << ": going on from the one before\n";
      return 0;
    }
    dir = o.out_dir.empty() ? "results/" + c.name : o.out_dir;
    // Only now, when the input is known to be good; in a distributed run rank 0 alone writes.
    if (root) prepare_output_dir(dir, o.force);
    return 0;
  });
  // Every rank reads the same case and meets the same errors; the folder is rank 0's: if it
  // refuses, all stop.
  if (const long worst = mpi::max(static_cast<long>(setup)); worst != 0)
    return static_cast<int>(worst);

  const auto t0 = Clock::now();
  // Every rank writes its piece of the frames (distributed); rank 0 the rest.
  OutputWriter writer(sim->model(), c.output, dir, c.end_time, &sim->profile(),
                      {mpi::rank(), mpi::ranks(), sim->rank_tets()});
  sim->add_observer(&writer, mpi::ranks() > 1 ? "output:pvtu+history" : "output:vtu+history");
  std::unique_ptr<GaugeWriter> gauges;  // distributed: the owners of the cells send their fields
  if (!c.output.gauges.empty()) {
    gauges = std::make_unique<GaugeWriter>(sim->model().mesh, c.output, dir, c.end_time,
                                           mpi::ranks() > 1 ? &sim->partition().tet_rank : nullptr,
                                           mpi::rank());
    sim->add_observer(gauges.get(), "output:gauges");
  }
  // Interpenetration at every frame, independent of the contact code (bodies ≥ 2, or
  // particles: a particle may not be inside any body). Distributed: measured by every rank
  // alike, for its piece's nodes.
  std::unique_ptr<PenetrationProbe> probe;
  if (sim->model().mesh.bodies.size() >= 2 || sim->model().particles) {
    probe = std::make_unique<PenetrationProbe>(sim->model());
    writer.set_penetration_probe(probe.get());
    sim->add_module("diagnostics:penetration");
  }
  Progress progress(o.quiet || !root, c.end_time);
  std::size_t falls = 0;  // step collapses said so far
  ReferenceRecorder references(c.references);
  std::vector<std::pair<long, double>> restarts;  // the checkpoints this run went on from
  // A checkpoint holds the simulation, then what the observers keep: the frames and history,
  // the probe's lists, the references measured, the gauges' rows.
  const auto persist_run = [&](Archive& ar) {
    sim->persist(ar);
    writer.persist(ar);
    if (probe) probe->persist(ar);
    references.persist(ar);
    ar(restarts);
    if (gauges) gauges->persist(ar);
  };
  CheckpointClock checkpoints(c.output);
  if (!o.restart.empty()) {
    try {
      Archive ar(std::move(restart.payload));
      persist_run(ar);
      if (!ar.at_end()) throw ArchiveError("data left over after the last section");
    } catch (const std::exception& e) {  // ArchiveError; a damaged size's bad_alloc too
      if (root)
        std::cerr << "tetcontact: error: " << restart.path << ": cannot be read back: " << e.what()
                  << "\n";
      return 2;
    }
    checkpoints.passed(sim->state().t);
    restarts.emplace_back(restart.header.step, restart.header.t);
    for (; falls < sim->step_collapses().size(); ++falls)
      warnings.push_back(sim->step_collapses()[falls].message());
    if (root)
      std::cerr << "tetcontact: note: restarting from " << restart.path << " (step "
                << restart.header.step << ", t = " << fmt(restart.header.t) << " s)\n";
  }
  // What the checkpoints say of themselves: the build and the inputs (read once, when written).
  const CheckpointHeader header = checkpoints.on()
                                      ? CheckpointHeader{program_identity(), inputs_hash(o, c)}
                                      : CheckpointHeader{};
  const long kill_step = kill_at_step();
  long stop_signal = 0;  // the signal that stopped the run (every rank alike)
  long checkpoint_step = -1;
  bool checkpoint_failed = false;  // said once; the run goes on without that checkpoint
  const auto write_now = [&](const Simulation& s) {
    sim->gather_state();  // distributed: every tet's fields, on every rank alike
    checkpoint_step = s.state().step;
    if (!root) return;
    Archive ar;
    persist_run(ar);
    CheckpointHeader h = header;
    h.step = s.state().step;
    h.t = s.state().t;
    try {
      write_checkpoint(dir, h, ar.bytes(), c.output.checkpoint_keep);
    } catch (const OutputError& e) {
      if (checkpoint_failed) return;
      checkpoint_failed = true;
      const std::string w = std::string("checkpoint not written (the run goes on): ") + e.what();
      warnings.push_back(w);
      std::cerr << (o.quiet ? "" : "\n") << "tetcontact: warning: " << w << "\n";
    }
  };
  if (checkpoints.on()) {
    std::signal(SIGTERM, note_stop_signal);
    std::signal(SIGINT, note_stop_signal);
  }
  RunHooks hooks;
  hooks.references = &references;
  hooks.stop = [&] { return stop_signal != 0; };
  hooks.each_step = [&](const Simulation& s) {
    progress.update(s.state());
    for (; falls < s.step_collapses().size(); ++falls) {
      const std::string w = s.step_collapses()[falls].message();
      warnings.push_back(w);
      if (root) std::cerr << (o.quiet ? "" : "\n") << "tetcontact: warning: " << w << "\n";
    }
    if (checkpoints.on() && checkpoints.due(s.state()) && !s.done()) {
      checkpoints.passed(s.state().t);
      write_now(s);
    }
    if (s.state().step == kill_step) std::raise(kill_signal());
    if (!checkpoints.on() || s.done()) return;
    // A stop asked by a signal: on every rank at the same step (the largest over the ranks).
    stop_signal = mpi::ranks() > 1 ? mpi::max(static_cast<long>(g_stop_signal))
                                   : static_cast<long>(g_stop_signal);
    if (stop_signal != 0 && checkpoint_step != s.state().step) write_now(s);
  };
  const std::string status = run_to_end(*sim, hooks);
  if (status == "interrupted") {
    progress.done();
    writer.close();  // the history and gauges so far in place (a restart writes them anew)
    if (gauges) gauges->close();
    if (root) {
      std::string sets;
      for (const std::string& s : o.overrides) sets += " --set '" + s + "'";
      std::cerr << "tetcontact: stopped by signal " << stop_signal << " after step "
                << sim->state().step << " (t = " << fmt(sim->state().t)
                << " s), its checkpoint written: go on with `tetcontact run " << o.case_path << sets
                << " --restart " << dir << "`\n";
    }
    return static_cast<int>(128 + stop_signal);
  }
  int code = status == "ok" ? 0 : 1;
  progress.done();
  sim->gather_state();  // distributed: the tets' fields whole for the summary and references
  const double communication = mpi::max(mpi::seconds());
  // The other ranks end with rank 0's code (a missed check is known to rank 0 alone).
  if (!root) return std::stoi(mpi::broadcast("", 0));
  try {
    code = report_run(o, c, *sim, writer,
                      {dir, status, code, seconds_since(t0), communication, warnings, &references,
                       gauges.get(), restarts});
  } catch (...) {
    mpi::broadcast("1", 0);
    throw;
  }
  mpi::broadcast(std::to_string(code), 0);
  return code;
}

namespace {

// Rank 0's part after the run: the summary with the case's checks, and the table.
int report_run(const RunOptions& o, const Case& c, const Simulation& sim, OutputWriter& writer,
               RunRecord run) {
  int code = run.code;
  writer.close();
  if (run.gauges) run.gauges->close();
  RunSummary summary = summarize(c, sim, writer, run.status, run.wall);
  summary.out_dir = run.dir;
  summary.gauge_rows = run.gauges ? run.gauges->rows() : 0;
  summary.restarts = run.restarts;
  summary.warnings = run.warnings;
  summary.regimes = regime_notes(c, sim.model());
  summary.communication = run.communication;
  // The case's stated bounds (`expect`), each against its summary figure: failed when the run
  // did not end ok.
  if (!c.expect.empty()) {
    ExpectFigures figures;
    figures.momentum_error = momentum_error(sim.first_sample(), sim.last_sample());
    figures.energy_balance = sim.balance_error_max();
    if (writer.measured_penetration()) {
      figures.penetration = writer.penetration_max();
      figures.particles_inside_end = writer.penetration_last().particles_inside;
    }
    summary.expect = judge_expect(c.expect, figures);
    for (ExpectResult& e : summary.expect) e.pass = e.pass && code == 0;
    if (o.check && !expect_pass(summary) && code == 0) code = 1;
  }
  if (code == 0 && !c.references.empty()) {
    summary.references = run.references->finish(sim.model(), sim.state(), sim.run_figures());
    if (o.check && !references_pass(summary)) code = 1;
  }
  if (c.shield_equation.declared) {
    summary.shield_equation = judge_shield_equation(c, summary.references);
    if (!summary.shield_equation->note.empty())
      std::cerr << "tetcontact: note: " << summary.shield_equation->note << "\n";
  }
  if (!c.mesh_study.cells_across.empty()) summary.mesh_study = c.mesh_study;
  write_file_atomic(run.dir + "/summary.json", summary_json(summary).dump(2) + "\n");
  // The run has ended: a restart of it is refused, so its checkpoints are of no more use.
  std::error_code ec;
  std::filesystem::remove_all(checkpoint_folder(run.dir), ec);
  if (!o.quiet || code != 0) print_table(summary);
  if (o.check && code != 0 && run.status == "ok")
    std::cerr << "tetcontact: check failed: a reference value or an expected bound is missed\n";
  if (run.status != "ok") std::cerr << "tetcontact: run failed: " << run.status.substr(8) << "\n";
  return code;
}

}  // namespace

}  // namespace tc
