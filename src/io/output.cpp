#include "tetcontact/io/output.hpp"
#include "tetcontact/model/persist.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>

#include "tetcontact/io/vtk.hpp"
#include "tetcontact/parallel/mpi.hpp"

namespace tc {

OutputWriter::OutputWriter(const Model& model, const OutputSpec& spec, std::string dir,
                           double end_time, const StepProfile* profile, const OutputPiece& piece)
    : model_(model),
      spec_(spec),
      dir_(std::move(dir)),
      end_time_(end_time),
      profile_(profile),
      piece_(piece) {
  for (const auto& stage : profile_->stages) stage_seconds_.push_back(stage.second);
  if (piece_.rank != 0) return;  // the history is rank 0's
  history_ = std::make_unique<AtomicFile>(dir_ + "/history.csv");
  auto& h = history_->stream();
  h << "step,t,dt,kinetic,internal,plastic_work,viscous_work,boundary_work,wall_work,total,"
       "balance_error,momentum_x,momentum_y,momentum_z";
  for (const RigidWall& w : model_.walls) h << ",wall_force_" << w.name;
  if (model_.contact) h << ",contact_work,contact_heat,contact_force,contacts";
  if (model_.element.fracture) h << ",damaged,destroyed";
  if (model_.particles) h << ",particles,particle_mass";
  if (spec_.penetration_every_step) h << ",nodes_inside,crossings";
  for (const auto& stage : profile_->stages) h << ",seconds_" << stage.first;
  h << '\n';
}

void OutputWriter::observe(const State& st, const Sample& s) {
  const bool final = s.final || s.t >= end_time_;
  std::vector<double> depth;
  if (probe_ && spec_.penetration_every_step) depth = measure_penetration(st);
  if (history_ && (s.step % spec_.history_every == 0 || final)) {
    auto& h = history_->stream();
    h << s.step;
    for (double v :
         {s.t, s.dt, s.kinetic, s.internal, s.plastic_work, s.viscous_work, s.boundary.work,
          s.walls.work, s.total, s.balance_error, s.momentum.x(), s.momentum.y(), s.momentum.z()})
      h << ',' << format_double(v);
    for (double f : s.wall_force) h << ',' << format_double(f);
    if (model_.contact)
      h << ',' << format_double(s.contact.work) << ',' << format_double(s.contact_heat) << ','
        << format_double(s.contact_force) << ',' << s.contacts;
    if (model_.element.fracture) h << ',' << s.damaged << ',' << s.destroyed;
    if (model_.particles) h << ',' << s.particles << ',' << format_double(s.particle_mass);
    if (probe_ && spec_.penetration_every_step)
      h << ',' << penetration_last_.nodes_inside << ',' << penetration_last_.crossings;
    for (std::size_t k = 0; k < profile_->stages.size(); ++k) {
      const double now = profile_->stages[k].second;
      h << ',' << format_double(now - stage_seconds_[k]);
      stage_seconds_[k] = now;
    }
    h << '\n';
    ++rows_;
  }
  if (frame_due(s)) {
    write_frame(st, s.t, probe_ && spec_.penetration_every_step ? &depth : nullptr);
    while (next_frame_ <= s.t + 1e-9 * spec_.interval) next_frame_ += spec_.interval;
  }
}

// A frame at the first sample at or after each multiple of the interval, and at the end.
bool OutputWriter::frame_due(const Sample& s) const {
  return s.t >= next_frame_ - 1e-9 * spec_.interval || s.final || s.t >= end_time_;
}

// The penetration at a time level: the run's maxima and last measure updated; the per-node
// depth returned for the frame.
std::vector<double> OutputWriter::measure_penetration(const State& st) {
  const auto t0 = std::chrono::steady_clock::now();
  Penetration p = probe_->measure(st);
  probe_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ++penetration_samples_;
  keep_largest(penetration_max_, p);
  std::vector<double> depth = std::move(p.node_depth);
  penetration_last_ = std::move(p);
  return depth;
}

// `depth`: this time level's penetration depths when already measured (every_step), else null.
void OutputWriter::write_frame(const State& st, double t, std::vector<double>* depth_measured) {
  if (!frames_.empty() && frames_.back().first == t) return;
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04zu.vtu", frames_.size());
  std::vector<double> depth;
  if (depth_measured)
    depth = std::move(*depth_measured);
  else if (probe_)
    depth = measure_penetration(st);
  if (piece_.ranks == 1) {
    write_file_atomic(dir_ + "/" + name, vtu_frame(model_, st, spec_.fields, depth, spec_.format));
  } else {
    // Each rank its piece; once all are written (the collective), rank 0 the file that joins
    // them.
    const std::size_t frame = frames_.size();
    const auto piece_name = [&](int rank) {
      char p[48];
      std::snprintf(p, sizeof p, "frame_%04zu_r%d.vtu", frame, rank);
      return std::string(p);
    };
    std::string arrays;
    write_file_atomic(
        dir_ + "/" + piece_name(piece_.rank),
        vtu_piece(model_, st, spec_.fields, depth, spec_.format, *piece_.tets, &arrays));
    mpi::max(0L);
    std::snprintf(name, sizeof name, "frame_%04zu.pvtu", frame);
    if (piece_.rank == 0) {
      std::vector<std::string> pieces;
      for (int r = 0; r < piece_.ranks; ++r) pieces.push_back(piece_name(r));
      write_file_atomic(dir_ + "/" + name, pvtu_frame(arrays, pieces));
    }
  }
  frames_.emplace_back(t, name);
  if (piece_.rank != 0) return;  // the series and the particles are rank 0's
  // Keep the series current so that a run stopped midway still opens in ParaView.
  write_file_atomic(dir_ + "/case.pvd", pvd_series(frames_));
  if (model_.particles) {  // the particles: a point series of their own, frame for frame
    std::snprintf(name, sizeof name, "particles_%04zu.vtu", frames_.size() - 1);
    write_file_atomic(dir_ + "/" + name, vtu_particles(model_, st, spec_.format));
    particle_frames_.emplace_back(t, name);
    write_file_atomic(dir_ + "/particles.pvd", pvd_series(particle_frames_));
  }
}

void OutputWriter::close() {
  if (history_) history_->commit();
}

GaugeWriter::GaugeWriter(const Mesh& mesh, const OutputSpec& spec, const std::string& dir,
                         double end_time, const std::vector<int>* tet_rank, int rank)
    : gauges_(mesh, spec.gauges),
      interval_(spec.gauge_interval),
      end_time_(end_time),
      tet_rank_(tet_rank),
      rank_(rank) {
  if (rank_ != 0) return;  // the file is rank 0's
  file_ = std::make_unique<AtomicFile>(dir + "/gauges.csv");
  auto& h = file_->stream();
  h << "step,t";
  for (const GaugeSpec& g : gauges_.specs())
    for (const char* q : {"x", "y", "z", "vx", "vy", "vz", "pressure", "sxx", "syy", "szz", "sxy",
                          "syz", "sxz", "plastic_strain", "temperature", "damage"})
      h << ',' << g.name << ':' << q;
  h << '\n';
}

void GaugeWriter::observe(const State& st, const Sample& s) {
  const bool final = s.final || s.t >= end_time_;
  if (!(interval_ == 0.0 || s.t >= next_ - 1e-9 * interval_ || final)) return;
  if (interval_ > 0.0)
    while (next_ <= s.t + 1e-9 * interval_) next_ += interval_;
  std::vector<GaugeReading> readings = gauges_.read(st);
  if (tet_rank_) {
    // A cell's fields are current on the rank that owns it: it sends them, in gauge order.
    for (GaugeReading& r : readings) {
      if (r.cell < 0) continue;
      std::array<double, 12> f;
      std::copy(r.stress.data(), r.stress.data() + 9, f.begin());
      f[9] = r.pressure;
      f[10] = r.plastic_strain;
      f[11] = r.temperature;
      std::string bytes(sizeof f, '\0');
      std::memcpy(bytes.data(), f.data(), sizeof f);
      bytes = mpi::broadcast(bytes, (*tet_rank_)[static_cast<std::size_t>(r.cell)]);
      std::memcpy(f.data(), bytes.data(), sizeof f);
      std::copy(f.begin(), f.begin() + 9, r.stress.data());
      r.pressure = f[9];
      r.plastic_strain = f[10];
      r.temperature = f[11];
    }
  }
  ++rows_;
  if (!file_) return;
  auto& h = file_->stream();
  h << s.step << ',' << format_double(s.t);
  for (const GaugeReading& r : readings) {
    if (r.cell < 0) {  // no cell holds the point: not measured
      h << std::string(16, ',');
      continue;
    }
    for (int i = 0; i < 3; ++i) h << ',' << format_double(r.x[i]);
    for (int i = 0; i < 3; ++i) h << ',' << format_double(r.v[i]);
    h << ',' << format_double(r.pressure);
    for (const auto& [i, j] : {std::pair{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}})
      h << ',' << format_double(r.stress(i, j));
    h << ',' << format_double(r.plastic_strain) << ',' << format_double(r.temperature) << ','
      << static_cast<int>(r.damage);
  }
  h << '\n';
}

void OutputWriter::persist(Archive& ar) {
  ar.section("output");
  ar(penetration_samples_, probe_seconds_, stage_seconds_, rows_, next_frame_, frames_,
     particle_frames_, penetration_max_, penetration_last_);
  std::string history = history_ && !ar.loading() ? history_->written() : std::string();
  ar(history);
  if (ar.loading() && history_) history_->rewrite(history);
}

void GaugeWriter::persist(Archive& ar) {
  ar.section("gauge rows");
  gauges_.persist(ar);
  ar(next_, rows_);
  std::string rows = ar.loading() || !file_ ? std::string() : file_->written();
  ar(rows);
  if (ar.loading() && file_) file_->rewrite(rows);
}

}  // namespace tc
