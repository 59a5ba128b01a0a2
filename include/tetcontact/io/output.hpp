// The run's files: the ParaView series (case.pvd + frame_NNNN.vtu; with fracture particles
// also particles.pvd + particles_NNNN.vtu), history.csv.
// summary.json is written by the app from the finished run.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tetcontact/diagnostics/gauges.hpp"
#include "tetcontact/diagnostics/penetration.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/io/files.hpp"
#include "tetcontact/model/sample.hpp"

namespace tc {

class Archive;

/// A distributed run's share of the output: each rank writes the piece of its
/// tets at every frame (frame_NNNN_rR.vtu); rank 0 joins them in frame_NNNN.pvtu and writes
/// the series, the history and the particles. Default: one process, whole frames.
struct OutputPiece {
  int rank = 0, ranks = 1;
  const std::vector<Index>* tets = nullptr;  // this rank's tets (ranks > 1)
};

class OutputWriter : public Observer {
 public:
  /// `dir` must have been prepared (prepare_output_dir). `profile` supplies the stage timings
  /// written to the history.
  OutputWriter(const Model& model, const OutputSpec& spec, std::string dir, double end_time,
               const StepProfile* profile, const OutputPiece& piece = {});
  void observe(const State& st, const Sample& sample) override;
  /// Writes case.pvd and moves history.csv into place. Call after the run, also a failed one:
  /// what was written is true data up to the failure.
  void close();
  std::size_t frames() const { return frames_.size(); }
  /// Measures interpenetration at every frame (the diagnostics; off the contact path),
  /// writes it per node as `penetration_depth`, and keeps the run's maxima.
  void set_penetration_probe(PenetrationProbe* probe) { probe_ = probe; }
  /// Maxima over the frames: nodes_inside, max_depth, max_depth_over_h, crossings.
  const Penetration& penetration_max() const { return penetration_max_; }
  /// The measure at the last frame (the run's end).
  const Penetration& penetration_last() const { return penetration_last_; }
  bool measured_penetration() const { return probe_ != nullptr && !frames_.empty(); }
  /// Seconds the penetration measures took (part of the output stage).
  double probe_seconds() const { return probe_seconds_; }
  /// Time levels the penetration was measured at (every frame, or every step with
  /// diagnostics.every_step).
  long penetration_samples() const { return penetration_samples_; }
  /// What a checkpoint holds of it: the frames written, the next one due, the history so far
  /// and the penetration's maxima (the probe's own lists are the probe's).
  void persist(Archive& ar);

 private:
  bool frame_due(const Sample& s) const;
  void write_frame(const State& st, double t, std::vector<double>* depth);
  std::vector<double> measure_penetration(const State& st);
  long penetration_samples_ = 0;

  double probe_seconds_ = 0.0;
  const Model& model_;
  OutputSpec spec_;
  std::string dir_;
  double end_time_;
  const StepProfile* profile_;
  OutputPiece piece_;
  std::unique_ptr<AtomicFile> history_;  // rank 0's
  std::vector<double> stage_seconds_;    // at the previous history row
  long rows_ = 0;
  double next_frame_ = 0.0;
  std::vector<std::pair<double, std::string>> frames_, particle_frames_;
  PenetrationProbe* probe_ = nullptr;
  Penetration penetration_max_, penetration_last_;
};

/// gauges.csv: per row the step and time, then per gauge (columns "NAME:quantity") its
/// position, velocity, the cell's pressure, stress (s − p I), plastic strain, temperature and
/// damage (0 intact, 1 damaged, 2 destroyed, 3 a particle); empty where no cell holds a space
/// gauge's point. A row at the first step at or after each multiple of the interval (0: every
/// step) and at the end. Distributed (`tet_rank`, the partition's rank of each tet, and this
/// process's `rank`): every rank reads the gauges (the nodes are whole on each), the rank that
/// owns a gauge's cell sends the cell's fields to the others (a collective per gauge and row),
/// and rank 0 writes the file: the rows of one process, bit for bit.
class GaugeWriter : public Observer {
 public:
  GaugeWriter(const Mesh& mesh, const OutputSpec& spec, const std::string& dir, double end_time,
              const std::vector<int>* tet_rank = nullptr, int rank = 0);
  void observe(const State& st, const Sample& sample) override;
  /// Moves gauges.csv into place (also after a failed run: its rows are true data).
  void close() {
    if (file_) file_->commit();
  }
  /// What a checkpoint holds of it: the rows so far and the next one due.
  void persist(Archive& ar);
  long rows() const { return rows_; }

 private:
  Gauges gauges_;
  double interval_, end_time_, next_ = 0.0;
  const std::vector<int>* tet_rank_;  // distributed: each tet's rank; null on one process
  int rank_;
  std::unique_ptr<AtomicFile> file_;  // rank 0's
  long rows_ = 0;
};

}  // namespace tc
