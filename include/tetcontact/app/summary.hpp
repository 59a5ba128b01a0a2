// A run's summary as plain data (RunSummary, gathered once from the simulation, the case and the
// output by summarize()), and its one writer: summary.json and the console table. This is the
// one place where the summary's key names live (docs/guide/outputs.md lists each with its unit).
// Sections a run does not have are empty here and null in the file: "not measured", never zero.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tetcontact/diagnostics/balance.hpp"
#include "tetcontact/diagnostics/expect.hpp"
#include "tetcontact/diagnostics/penetration.hpp"
#include "tetcontact/diagnostics/reference.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/io/json.hpp"
#include "tetcontact/io/output.hpp"
#include "tetcontact/solver/simulation.hpp"

namespace tc {

/// A number as the table prints it (printf format `f`), and a vector as [x, y, z].
std::string fmt(double v, const char* f = "%.4g");
std::string fmt3(const Vec3& v);

struct RunSummary {
  // The run.
  std::string case_name, case_file, status, material_library, out_dir;
  std::vector<std::pair<std::string, double>> parameters;  // the values the expressions used
  long steps = 0;
  double time = 0.0, end_time = 0.0, wall = 0.0;
  // Why the run ended ("end_time", "released"; "" when it failed), the case's
  // end_when_released (0: none) and the last push of a wall or contact (< 0: none).
  std::string ended_by;
  double end_when_released = 0.0, last_push = -1.0;
  std::vector<std::string> modules, warnings, regimes;
  std::size_t nodes = 0, tets = 0, surface_faces = 0, surface_edges = 0, frames = 0;
  long gauge_rows = 0;  // rows of gauges.csv (0: no gauges recorded)
  /// The checkpoints the run went on from (run --restart), oldest first: step and time. Its
  /// wall_seconds are the last process's; its timings, the stages' over every process.
  std::vector<std::pair<long, double>> restarts;
  std::vector<std::string> symmetry;  // the symmetry planes' names (the whole: 2^size copies)
  std::vector<std::pair<std::string, double>> stages;  // seconds per stage (StepProfile)
  std::optional<double> probe_seconds;  // the part of `output` the penetration probe took
  int threads = 1;
  // Balance and bodies.
  Sample first, last;
  double balance_error_max = 0.0;
  bool contact_work = false;  // contact or particles: their work is measured
  std::vector<BodyStats> bodies;
  struct Wall {
    std::string name;
    double max_force = 0.0;  // N
  };
  std::vector<Wall> walls;
  // The time step: its last, smallest and first, the tet that limits it, its falls.
  struct Critical {
    std::string body;
    long body_tet = 0;
    double volume_ratio = 0.0;
    long damage = 0;
  };
  struct TimeStep {
    double cfl = 0.0, min = 0.0, first = 0.0;
    long critical_tet = -1;
    // With SPH particles: the steps they set and their smallest step.
    std::optional<std::pair<long, double>> particles;
    std::optional<Critical> critical;
    std::vector<StepCollapse> collapses;
  } time_step;
  // Contact between bodies (none without it).
  struct Contact {
    ContactLedger ledger;
    bool edge_edge = false, verify = false;
    std::string broadphase;
    double separation = 0.0;
  };
  std::optional<Contact> contact;
  // Penetration (none where it was not measured).
  struct PenetrationMeasures {
    Penetration max;
    bool particles = false;
    long particles_inside_at_end = 0;
    bool every_step = false;
    long samples = 0;
  };
  std::optional<PenetrationMeasures> penetration;
  // Fracture, and the particles with their ledger (none when the case makes no particles).
  bool fracture = false;
  struct FromBody {
    std::string name;
    long particles = 0;
    double mass = 0.0;
    long ductile_failed = 0, ductile_failed_at_floor = 0;  // its cells, as the run's below
    std::optional<double> erosion_step;  // s: its cells erode below it (erosion by the step)
  };
  struct Particles {
    ConversionLedger ledger;
    long particle_contacts = 0, particles_moved_out = 0;
    double particle_move_max = 0.0, particle_kinetic_energy = 0.0;
    std::optional<long> ductile_failed;  // with Johnson–Cook ductile failure
    // Of those, the cells whose damage accrued more than half with ε_f at its floor (the
    // law's own ε_f below it: a set with D1 < 0 at high triaxiality).
    std::optional<long> ductile_failed_at_floor;
    std::vector<FromBody> from_bodies;
    // fracture.debris: sph — the particles' material at the end (sums over them).
    bool sph = false;
    double sph_internal = 0.0, sph_plastic_work = 0.0, sph_pair_heat = 0.0;
    double sph_neighbours = 0.0;  // mean neighbours a particle (its images included)
    bool sph_faces = false;       // the bodies' faces met through the kernel
    double sph_face_pairs = 0.0;  // mean faces within a particle's reach (its images' too)
    long sph_damaged = 0;         // particles damaged or destroyed (no tension)
  };
  std::optional<Particles> particles;
  std::optional<long> eroded, particles_moved_out;  // the safeguards the run has
  // Processes.
  Partition partition;
  double communication = 0.0;  // s, the largest over the ranks
  // The case's checks: its bounds (each failing when the run did not end ok) and references.
  std::vector<ExpectResult> expect;
  std::vector<ReferenceResult> references;
  // The case's shield equation beside the engine's verdict (none when the case declares none).
  struct ShieldEquation {
    WhippleShot shot;
    ShieldEquationVerdict equation;
    std::string verdict;                    // the `reference:` entry set against it
    std::optional<bool> engine_perforated;  // none: the run did not measure it
    std::string note;                       // when the two disagree, what to make of it
  };
  std::optional<ShieldEquation> shield_equation;
  std::optional<MeshStudySpec> mesh_study;  // the case's, with the run's and the file's cells
};

/// What a run says before it starts of its case's shot and cells: Christiansen's verdict
/// (`shield_equation:`) and, on cells coarser than the file's own, the mesh study's note.
std::vector<std::string> shield_notes(const Case& c);

/// The equation's verdict beside the engine's, once the references are measured.
RunSummary::ShieldEquation judge_shield_equation(const Case& c,
                                                 const std::vector<ReferenceResult>& refs);

/// Everything but the case's checks and the regimes, from the run as it ended.
RunSummary summarize(const Case& c, const Simulation& sim, const OutputWriter& writer,
                     const std::string& status, double wall);

/// summary.json.
Json summary_json(const RunSummary& s);

/// The final table on stdout: status, steps, energy, momentum, bodies, timings, output, then
/// each reference and each bound.
void print_table(const RunSummary& s);

/// summary.expect: each bound with its figure (null when not measured) and verdict.
Json expect_json(const std::vector<ExpectResult>& expect);

/// Whether every bound and every reference the run states passes.
bool expect_pass(const RunSummary& s);
bool references_pass(const RunSummary& s);

}  // namespace tc
