// tetcontact: command-line entry point. CLI11 parses the subcommands, their options, --help
// and usage errors; each subcommand fills its options struct and calls its command.
//
// Exit codes: 0 success, 1 run failure (summary.json says why) or a missed check, 2 bad usage
// or bad input (nothing written).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "tetcontact/app/campaign.hpp"
#include "tetcontact/app/ccd.hpp"
#include "tetcontact/app/limit.hpp"
#include "tetcontact/app/partition.hpp"
#include "tetcontact/app/profile.hpp"
#include "tetcontact/app/run.hpp"
#include "tetcontact/app/stress.hpp"
#include "tetcontact/app/sweep.hpp"
#include "tetcontact/parallel/mpi.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace {

constexpr int k_bad_usage = 2;

const char* k_set_help =
    "override a case key, e.g. --set solver.cfl=0.3 or --set bodies.0.velocity=[0,0,-100] "
    "(repeatable; VALUE is YAML)";

// --set KEY=VALUE, repeatable, one value each.
void add_overrides(CLI::App* cmd, std::vector<std::string>& overrides) {
  cmd->add_option("--set", overrides, k_set_help)
      ->type_name("KEY=VALUE")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

// --vary KEY=V1,V2,...: a case key and its values.
CLI::Option* add_vary(CLI::App* cmd,
                      std::vector<std::pair<std::string, std::vector<std::string>>>& vary,
                      const std::string& help) {
  return cmd
      ->add_option_function<std::vector<std::string>>(
          "--vary",
          [&vary](const std::vector<std::string>& all) {
            for (const std::string& v : all) {
              const std::size_t eq = v.find('=');
              if (eq == std::string::npos || eq == 0 || eq + 1 == v.size())
                throw CLI::ValidationError("--vary", "needs KEY=V1,V2,...: '" + v + "'");
              vary.emplace_back(v.substr(0, eq), tc::split_values(v.substr(eq + 1)));
            }
          },
          help)
      ->type_name("KEY=V1,V2,...")
      ->expected(1);
}

CLI::App* add_run(CLI::App& app, tc::RunOptions& o) {
  CLI::App* cmd = app.add_subcommand("run", "run a case and write its results");
  cmd->add_option("case", o.case_path, "the case file (YAML)")->required();
  cmd->add_option("--out", o.out_dir,
                  "output directory (default results/<case name>); created; a non-empty one is "
                  "refused");
  cmd->add_flag("--force", o.force, "reuse a non-empty --out, replacing a previous run's files");
  cmd->add_option("--restart", o.restart,
                  "go on from the newest checkpoint of this run folder (or of its checkpoints "
                  "folder, or from one checkpoint file), in that folder; the same case, "
                  "overrides and build as the run that wrote it (output.checkpoint)")
      ->type_name("DIR");
  add_overrides(cmd, o.overrides);
  cmd->add_flag("--quiet", o.quiet,
                "no progress and no final table (notes and warnings still go to stderr)");
  cmd->add_flag("--check", o.check,
                "exit 1 when the run misses a bound of the case's `expect:` or a value of its "
                "`reference:` (summary.json lists them in any case)");
  cmd->footer(
      "Writes into the output directory:\n"
      "  case.pvd, frame_NNNN.vtu   ParaView series (open case.pvd)\n"
      "  history.csv                energies, momentum and stage timings per step\n"
      "  summary.json               the run's summary (status, balance, bodies, timings)\n"
      "  checkpoints/step_N.ckpt    the state to restart from (output.checkpoint)\n"
      "Progress goes to stderr (a bar on a terminal, periodic lines otherwise), the final table\n"
      "to stdout. Exit codes: 0 success, 1 run failure or missed check, 2 bad input (nothing "
      "written).");
  return cmd;
}

CLI::App* add_check(CLI::App& app, tc::RunOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "check", "validate a case (file, meshes, first time step) without running it");
  cmd->add_option("case", o.case_path, "the case file (YAML)")->required();
  add_overrides(cmd, o.overrides);
  cmd->footer("Prints one line on success. Exit codes: 0 valid, 2 bad input.");
  return cmd;
}

CLI::App* add_ccd(CLI::App& app, tc::CcdOptions& c) {
  CLI::App* cmd = app.add_subcommand("ccd", "exact continuous collision queries from a file");
  cmd->add_option("file", c.file, "query file (data/ccd/README.md format)")->required();
  cmd->add_flag("--toi", c.toi,
                "after each 1, the earliest time of impact in [0, 1] (exact, rounded down to a "
                "double; the mean time then includes finding it)");
  cmd->add_flag("--fcl", c.fcl,
                "also FCL 0.7's cubic CCD on the same queries (its answers, errors and time)");
  cmd->add_option("--confirm", c.confirm,
                  "cgal: check every answer with the independent CGAL oracle (algebraic kernel "
                  "roots and signs): agreements, disagreements, undecided, time")
      ->check(CLI::IsMember({"cgal"}));
  cmd->add_flag("--json", c.json, "one object {\"ee\": {...}, \"vf\": {...}}");
  cmd->add_flag("--quiet", c.quiet, "no per-query lines");
  cmd->footer(
      "One query a line: TYPE [GT] 24 coordinates (ee: a0 a1 b0 b1 at t=0, then at t=1; vf: v\n"
      "f0 f1 f2 at t=0, then at t=1). Prints 0/1 per query, and with ground truth the false\n"
      "positives, false negatives and mean time per type. Times are batch means over >= 0.2 s.");
  return cmd;
}

CLI::App* add_stress(CLI::App& app, tc::StressOptions& s) {
  CLI::App* cmd =
      app.add_subcommand("stress", "exact CCD against degenerate query families, and micro-scenes");
  cmd->add_option("--seed", s.seed, "random seed (default 1)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--count", s.count, "queries per family (default 1000)")
      ->check(CLI::Range(1, 100000000));
  auto* scenes =
      cmd->add_option("--scenes", s.scenes_dir, "micro-scene folder (default data/cases/micro)");
  cmd->add_flag_callback(
         "--no-scenes", [&s] { s.scenes = false; }, "skip the micro-scenes")
      ->excludes(scenes);
  cmd->add_option("--solver-scenes", s.solver_scenes,
                  "generated whole-solver scenes to run (random angles, touching, sliding, 0.1 "
                  "to 7 km/s, verification on): any crossing or node inside fails (default 0)")
      ->check(CLI::Range(0, 100000));
  add_overrides(cmd, s.overrides);
  cmd->add_flag("--json", s.json,
                "one object with `families`, `disagreements`, `scenes`, `scenes_failed` and "
                "`solver_scenes`");
  cmd->footer(
      "Generates --count queries per degenerate family (parallel, collinear and crossing edges,\n"
      "zero-length edges, edges a few ulps from parallel, coplanar vertex-face, vertex on a\n"
      "face's edge or corner, collapsed faces), each with its answer known by construction and\n"
      "placed by an exact transformation, and compares the exact CCD with every answer. Then\n"
      "runs the micro-scenes (bodies in degenerate contact) through the solver; a scene passes\n"
      "with no NaN, no inverted element, momentum conserved to 1e-12 and the penetration bounds\n"
      "of its `expect:` section held at every step.\n"
      "Exit codes: 0 no disagreement and every scene passed, 1 otherwise, 2 bad usage or input.");
  return cmd;
}

CLI::App* add_sweep(CLI::App& app, tc::SweepOptions& w) {
  CLI::App* cmd = app.add_subcommand(
      "sweep", "error against run time over combinations of case keys (sweep.csv)");
  cmd->add_option("case", w.case_path, "the case file (YAML)")->required();
  add_vary(cmd, w.vary,
           "KEY=V1,V2,...: the values of a case key (a value may be a YAML list; keys joined by + "
           "take the same values); repeatable, the last varying fastest")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->required();
  cmd->add_option("--reference", w.reference,
                  "analytic (the case's references, default), finest (the run with the most "
                  "tets), or an earlier run's SUMMARY.json");
  cmd->add_option("--out", w.out_dir, "output directory (default results/<case name>-sweep)");
  cmd->add_flag("--force", w.force, "reuse a non-empty --out");
  add_overrides(cmd, w.overrides);
  cmd->add_flag("--quiet", w.quiet, "no table");
  cmd->footer(
      "Writes DIR/sweep.csv: per run the varied values, status, wall_seconds, steps, tets,\n"
      "error, each declared reference's error, momentum_error, energy_balance_max,\n"
      "penetration_depth_over_h and crossings. Plot with tools/post/plot_sweep.py DIR/sweep.csv.\n"
      "Exit codes: 0, 1 a run failed (its row says so), 2 bad input (nothing run).");
  return cmd;
}

CLI::App* add_limit(CLI::App& app, tc::LimitOptions& l) {
  CLI::App* cmd = app.add_subcommand(
      "limit", "bracket a ballistic limit: the value of a case key where a criterion flips");
  cmd->add_option("case", l.case_path, "the case file (YAML)")->required();
  cmd->add_option("--find", l.find, "the case key narrowed, e.g. parameters.d")->required();
  cmd->add_option_function<std::vector<double>>(
         "--between",
         [&l](const std::vector<double>& v) {
           l.lo = v[0];
           l.hi = v[1];
         },
         "LO HI: the key's values at the two ends (the criterion must differ there)")
      ->expected(2)
      ->required();
  cmd->add_option("--criterion", l.criterion,
                  "perforated:BODY: the case's `reference:` entry with measure perforated and "
                  "that body")
      ->required();
  add_vary(cmd, l.vary,
           "KEY=V1,V2,...: a second key, a bracket for each of its values (the curve)");
  cmd->add_option("--jobs", l.jobs,
                  "runs at once, each a process of one thread (default: the "
                  "cores)")
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--tolerance", l.tolerance,
                  "stop when the bracket's width is at most this fraction of its upper end "
                  "(default 0.05)")
      ->check(CLI::Range(1e-6, 1.0));
  cmd->add_option("--out", l.out_dir,
                  "output directory (default results/<case name>-limit); a folder holding an "
                  "earlier search's runs/ is resumed");
  add_overrides(cmd, l.overrides);
  cmd->add_flag("--quiet", l.quiet, "no progress lines");
  cmd->add_flag("--check", l.check,
                "check the case at both ends of the bracket at each --vary value as `check` does "
                "(the keys, the meshes, the first step); nothing runs, nothing is written");
  cmd->footer(
      "Each run is `tetcontact run` into DIR/runs/<KEY2=w>/<KEY=x>_<hash>/ (summary.json,\n"
      "run.log, run.key: the program's build, the case file, every override, the library);\n"
      "a finished run of the same inputs is read, not run again, so an interrupted search\n"
      "resumes. Writes DIR/limit.csv: per bracket the key, its ends, the criterion at each,\n"
      "runs, reused runs, wall_seconds (the search's elapsed time), run_seconds (the runs'\n"
      "own times added up; they run side by side) and status. Each run.log holds that run's\n"
      "table, notes and warnings.\n"
      "Exit codes: 0 every bracket found, 1 one was not (its line says why), 2 bad input.");
  return cmd;
}

CLI::App* add_campaign(CLI::App& app, tc::CampaignOptions& c) {
  CLI::App* cmd = app.add_subcommand(
      "campaign", "run a case once per row of a table of experiments and compare with them");
  cmd->add_option("case", c.case_path, "the case file, with a `campaign:` block")->required();
  cmd->add_option("table", c.table_path, "the table of experiments (CSV)")->required();
  cmd->add_option("--rows", c.rows,
                  "rows to run: clauses separated by ';', all met: row numbers and ranges "
                  "(1-20,35) or conditions on a column (angle=0; v<7; material!=Cu OFHC)");
  cmd->add_option("--jobs", c.jobs,
                  "runs at once, each a process of one thread (default: the cores)")
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--out", c.out_dir,
                  "output directory (default results/<case name>-campaign); a folder holding an "
                  "earlier campaign's runs/ is resumed");
  add_overrides(cmd, c.overrides);
  cmd->add_flag("--quiet", c.quiet, "no progress lines");
  cmd->add_flag("--check", c.check,
                "check the case, the table and the case every row makes; run nothing");
  cmd->footer(
      "Each row is `tetcontact run` into DIR/runs/row-<N>_<hash>/ (summary.json, run.log,\n"
      "run.key: the program's build, the case file, every override, the library); a finished\n"
      "run of the same inputs is read, not run again, so an interrupted campaign resumes, and\n"
      "another --set or another build runs anew. Writes\n"
      "DIR/predictions.csv (per row: inputs, predicted, measured, error, status),\n"
      "DIR/statistics.json (error percentiles, or confusion table and accuracy, per group) and\n"
      "DIR/campaign.png (tools/post/plot_campaign.py). Exit codes: 0, 1 a run failed (its line\n"
      "says why), 2 bad input: the case or the table (the row and column named), nothing run.");
  return cmd;
}

CLI::App* add_profile(CLI::App& app, tc::ProfileOptions& p) {
  CLI::App* cmd = app.add_subcommand(
      "profile", "broadphase pruning and cost per method (a case or two frames)");
  auto* case_opt = cmd->add_option("case", p.case_path, "the case file (case mode)");
  auto* frames = cmd->add_option("--frames", p.frames,
                                 "A.ply B.ply: a surface at a step's start "
                                 "and end (frames mode)")
                     ->expected(2);
  case_opt->excludes(frames);
  cmd->add_option("--broadphase", p.method,
                  "fcl_tree, fcl_sap, grid, sweep, brute_force or all (default)");
  cmd->add_option("--steps", p.steps, "case mode: steps per method (default 100)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--margin", p.margin, "frames mode: box inflation, m (default 0)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--repeat", p.repeat,
                  "frames mode: calls per method, the last one's times reported beside the "
                  "first's (default 1)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--json", p.json, "stdout is one JSON array, an object per method");
  cmd->add_option("--ccd-queries", p.ccd_queries,
                  "case mode: write the exact CCD queries of the first method's steps (contact "
                  "and verification) to FILE, in ccd's format: time them with ccd FILE --fcl")
      ->excludes(frames);
  add_overrides(cmd, p.overrides);
  return cmd;
}

CLI::App* add_partition(CLI::App& app, tc::PartitionOptions& p) {
  CLI::App* cmd = app.add_subcommand(
      "partition",
      "the decomposition a distributed run uses: pieces per rank, shared and ghost "
      "nodes, imbalance (METIS)");
  cmd->add_option("case", p.case_path, "the case file")->required();
  cmd->add_option("--ranks", p.ranks, "pieces (default 2)")->check(CLI::PositiveNumber);
  cmd->add_flag("--tets-only", p.tets_only,
                "balance the tets alone (default: tets and boundary faces, the contact work)");
  cmd->add_flag("--json", p.json, "stdout is one JSON object");
  add_overrides(cmd, p.overrides);
  cmd->footer("Exit codes: 0, 2 bad input (the case, or more ranks than tets).");
  return cmd;
}

// --threads N: the case's solver.threads, for this command (wins over --set solver.threads).
void add_threads(CLI::App* cmd, int& threads) {
  cmd->add_option("--threads", threads,
                  "threads (default: the case's solver.threads, else all cores); results are "
                  "bit-identical for any count")
      ->check(CLI::Range(1, 4096));
}

void apply_threads(int threads, std::vector<std::string>& overrides) {
  if (threads > 0) overrides.push_back("solver.threads=" + std::to_string(threads));
}

// Runs a command: bad input it did not classify itself is an internal error (exit 1).
template <class F>
int guarded(F&& command, int on_error = 1) {
  try {
    return command();
  } catch (const std::exception& e) {
    // stdio, not std::cerr: the other ranks' std::cerr is silenced, not their errors.
    std::fprintf(stderr, "tetcontact: %s%s\n",
                 on_error == k_bad_usage ? "error: " : "internal error: ", e.what());
    if (tc::mpi::ranks() > 1) {
      // An error the ranks did not meet together (they meet the case's, the run's and the
      // elements' together): the others cannot go on without this one.
      std::fflush(nullptr);
      tc::mpi::abort(on_error);
    }
    return on_error;
  }
}

int tetcontact_main(int argc, char** argv);

}  // namespace

// In a distributed run (mpirun -np N) every process runs the command and meets the same
// input errors and run failures; rank 0 alone speaks and writes, the others' output is
// discarded (their unexpected errors still reach stderr: tc::mpi::abort follows them).
int main(int argc, char** argv) {
  tc::mpi::init(&argc, &argv);
  if (tc::mpi::rank() != 0) {
    if (!std::freopen("/dev/null", "w", stdout)) return 1;
    std::cerr.rdbuf(nullptr);  // what rank 0 says too; errors of its own go through stdio
  }
  const int code = tetcontact_main(argc, argv);
  std::fflush(nullptr);
  tc::mpi::finalize();
  return code;
}

namespace {

int tetcontact_main(int argc, char** argv) {
  CLI::App app{"tetcontact: explicit contact–impact solver for tetrahedral meshes", "tetcontact"};
  app.set_version_flag("--version", std::string("tetcontact ") + TETCONTACT_VERSION);
  app.require_subcommand(1);
  app.footer(
      "Exit codes: 0 success, 1 run failure (summary.json says why), 2 bad input.\n"
      "Help for a command: tetcontact COMMAND --help.");
  tc::RunOptions run, check;
  tc::CcdOptions ccd;
  tc::StressOptions stress;
  tc::SweepOptions sweep;
  tc::ProfileOptions profile;
  tc::PartitionOptions partition;
  tc::LimitOptions limit;
  tc::CampaignOptions campaign;
  CLI::App* run_cmd = add_run(app, run);
  CLI::App* check_cmd = add_check(app, check);
  CLI::App* ccd_cmd = add_ccd(app, ccd);
  CLI::App* stress_cmd = add_stress(app, stress);
  CLI::App* sweep_cmd = add_sweep(app, sweep);
  CLI::App* profile_cmd = add_profile(app, profile);
  CLI::App* partition_cmd = add_partition(app, partition);
  CLI::App* limit_cmd = add_limit(app, limit);
  CLI::App* campaign_cmd = add_campaign(app, campaign);
  int run_threads = 0, sweep_threads = 0, profile_threads = 0;
  add_threads(run_cmd, run_threads);
  add_threads(sweep_cmd, sweep_threads);
  add_threads(profile_cmd, profile_threads);
  try {
    app.parse(argc, argv);
    if (profile_cmd->parsed() && profile.case_path.empty() == profile.frames.empty())
      throw CLI::ValidationError("profile", "give a case file or --frames A.ply B.ply");
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // help and version print and give 0
    return code == 0 ? 0 : k_bad_usage;
  }
  // Started as one of several processes (mpirun -np N, srun): only `run` is distributed;
  // every copy of another command would do the whole of it.
  if (tc::mpi::ranks() > 1 && !run_cmd->parsed()) {
    if (tc::mpi::rank() == 0)
      std::cerr << "tetcontact: error: started as one of " << tc::mpi::ranks()
                << " processes: only `run` runs distributed; run this command as one "
                   "process, with --threads N for the cores of a machine\n";
    return k_bad_usage;
  }
  apply_threads(run_threads, run.overrides);
  apply_threads(sweep_threads, sweep.overrides);
  apply_threads(profile_threads, profile.overrides);
  if (profile_threads > 0) tc::parallel::set_threads(profile_threads);  // frames mode: no case
  if (run_cmd->parsed()) return guarded([&] { return tc::run_case(run); });
  if (check_cmd->parsed()) return guarded([&] { return tc::check_case(check); });
  if (ccd_cmd->parsed()) return guarded([&] { return tc::ccd_command(ccd); });
  // A missing or bad micro-scene case is bad input.
  if (stress_cmd->parsed()) return guarded([&] { return tc::stress_command(stress); }, k_bad_usage);
  if (sweep_cmd->parsed()) return guarded([&] { return tc::sweep_command(sweep); });
  if (profile_cmd->parsed()) return guarded([&] { return tc::profile_command(profile); });
  if (partition_cmd->parsed()) return guarded([&] { return tc::partition_command(partition); });
  if (limit_cmd->parsed()) return guarded([&] { return tc::limit_command(limit); });
  if (campaign_cmd->parsed()) return guarded([&] { return tc::campaign_command(campaign); });
  return k_bad_usage;
}

}  // namespace
