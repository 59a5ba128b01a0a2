// The one run loop: a Simulation stepped to its end. `run` (and through it `limit`), `sweep`,
// `stress`, `profile` and the tests drive every run with it.
#pragma once

#include <functional>
#include <string>

#include "tetcontact/diagnostics/reference.hpp"
#include "tetcontact/solver/simulation.hpp"

namespace tc {

struct RunHooks {
  /// References measured at their time (a distributed run's state gathered first); null: none.
  ReferenceRecorder* references = nullptr;
  /// Called after every step.
  std::function<void(const Simulation&)> each_step;
  /// Stop after this many steps, without the final sample (profiling); < 0: run to end_time.
  long max_steps = -1;
  /// Asked after each step (after each_step): true stops the run there, without the final
  /// sample (a signal's stop, its state kept in a checkpoint).
  std::function<bool()> stop;
};

/// Steps `sim` to end_time and samples the final time level (Simulation::finish). Returns the
/// run's status: "ok"; "stopped" (max_steps reached first); "interrupted" (`stop` said so); or
/// "failed: WHAT" when the run could not go on (RunFailure: an inverted element, a non-finite
/// value, the case's solver.max_steps).
std::string run_to_end(Simulation& sim, const RunHooks& hooks = {});

}  // namespace tc
