// The run's files: the ParaView series (case.pvd + frame_NNNN.vtu), history.csv.
// summary.json is written by the app from the finished run.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tetcontact/io/case.hpp"
#include "tetcontact/io/files.hpp"
#include "tetcontact/solver/simulation.hpp"

namespace tc {

class OutputWriter : public Observer {
 public:
  /// `dir` must have been prepared (prepare_output_dir). `profile` supplies the stage timings
  /// written to the history.
  OutputWriter(const Model& model, const OutputSpec& spec, std::string dir, double end_time,
               const StepProfile* profile);
  void observe(const State& st, const Sample& sample) override;
  /// Writes case.pvd and moves history.csv into place. Call after the run, also a failed one:
  /// what was written is true data up to the failure.
  void close();
  std::size_t frames() const { return frames_.size(); }

 private:
  void write_frame(const State& st, double t);

  const Model& model_;
  OutputSpec spec_;
  std::string dir_;
  double end_time_;
  const StepProfile* profile_;
  AtomicFile history_;
  std::vector<double> stage_seconds_;  // at the previous history row
  long rows_ = 0;
  double next_frame_ = 0.0;
  std::vector<std::pair<double, std::string>> frames_;
};

}  // namespace tc
