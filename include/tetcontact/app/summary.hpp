// A run's summary.json and its console table, from the simulation, the case and the output:
// the one place where the summary's key names live (docs/guide/outputs.md lists each with its
// unit). Sections a run does not have are null: "not measured", never zero.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "tetcontact/diagnostics/expect.hpp"
#include "tetcontact/diagnostics/reference.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/io/json.hpp"
#include "tetcontact/io/output.hpp"
#include "tetcontact/solver/simulation.hpp"

namespace tc {

/// A number as the table prints it (printf format `f`), and a vector as [x, y, z].
std::string fmt(double v, const char* f = "%.4g");
std::string fmt3(const Vec3& v);

/// summary.json without the case's checks (expect, references) and the run's processes.
Json summary_json(const Case& c, const Simulation& sim, const OutputWriter& writer,
                  const std::string& status, double wall, const std::vector<std::string>& warnings);

/// summary.parallel: the processes and threads, and the decomposition of a distributed run;
/// `communication`: the largest time a rank spent in collectives, s.
Json parallel_json(const Simulation& sim, double communication);

/// The final table on stdout: status, steps, energy, momentum, bodies, timings, output.
void print_table(const Case& c, const Simulation& sim, const std::string& status,
                 const std::string& dir, std::size_t frames, double wall);

/// summary.expect: each bound the case states against its figure, failing when the run did not
/// end ok (`run_ok` false); `lines` gets the table's lines. Whether all pass.
bool expect_summary(const std::vector<ExpectResult>& results, bool run_ok, Json& list,
                    std::string& lines);

/// summary.references: each reference with its measure, unit, value, error and verdict.
Json references_json(const std::vector<ReferenceResult>& refs);

/// The table's line of each reference, its unit beside every number.
void print_references(const std::vector<ReferenceResult>& refs);

}  // namespace tc
