// A shipped case run to its end in-process, with its references measured at their time: what
// the validation tests read of it.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <limits>
#include <string>
#include <vector>

#include "../test_util.hpp"
#include "tetcontact/app/setup.hpp"
#include "tetcontact/diagnostics/reference.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/solver/run_loop.hpp"
#include "tetcontact/solver/simulation.hpp"

namespace tc::test {

struct CaseRun {
  std::vector<ReferenceResult> refs;
  double balance_error_max = 0.0;
  double momentum_error = 0.0;
  long tets = 0;
  double seconds = 0.0;  // setup and run, wall clock
  long steps = 0;
  double time = 0.0, end_time = 0.0, last_push = -1.0;  // s
  std::string ended_by;                                 // Simulation::ended_by
  Sample last;                                          // the final sample
  ContactLedger contact;                                // Simulation::contact_totals
  /// The named reference's measured value (a failure when it is missing or unmeasured).
  double measured(const std::string& name) const {
    for (const ReferenceResult& r : refs)
      if (r.spec->name == name) {
        EXPECT_TRUE(r.error.empty()) << name << ": " << r.error;
        return r.measured;
      }
    ADD_FAILURE() << "no measure '" << name << "'";
    return std::numeric_limits<double>::quiet_NaN();
  }
};

/// Runs the case `file` (relative to the source tree) with --set `overrides`.
inline CaseRun run_case(const std::string& file, const std::vector<std::string>& overrides = {}) {
  static std::vector<Case> keep;  // the references point into the case
  keep.push_back(load_case(source_path(file), overrides));
  const Case& c = keep.back();
  const auto start = std::chrono::steady_clock::now();
  Simulation sim(build_model(c), solver_settings(c));
  ReferenceRecorder references(c.references);  // the timed ones at their time
  RunHooks hooks;
  hooks.references = &references;
  EXPECT_EQ(run_to_end(sim, hooks), "ok") << file;
  CaseRun r;
  r.refs = references.finish(sim.model(), sim.state(), sim.run_figures());
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.tets = sim.model().mesh.tet_count();
  r.balance_error_max = sim.balance_error_max();
  r.momentum_error = momentum_error(sim.first_sample(), sim.last_sample());
  r.steps = sim.state().step;
  r.time = sim.last_sample().t;
  r.end_time = c.end_time;
  r.last_push = sim.last_push();
  r.ended_by = sim.ended_by();
  r.last = sim.last_sample();
  r.contact = sim.contact_totals();
  return r;
}

}  // namespace tc::test
