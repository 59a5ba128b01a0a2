// tetcontact: command-line entry point.
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "tetcontact/app/ccd.hpp"
#include "tetcontact/app/profile.hpp"
#include "tetcontact/app/run.hpp"
#include "tetcontact/app/stress.hpp"
#include "tetcontact/app/sweep.hpp"

namespace {

const char* k_usage =
    "usage: tetcontact <command> [options]\n"
    "\n"
    "commands:\n"
    "  run CASE.yaml     run a case and write its results\n"
    "  check CASE.yaml   validate a case (file, meshes, time step) without running it\n"
    "  ccd FILE          exact continuous collision queries (../shared/ccd format)\n"
    "  profile CASE.yaml | --frames A.ply B.ply\n"
    "                    broadphase pruning and cost per method\n"
    "  stress            exact CCD against degenerate query families with known answers\n"
    "  sweep CASE.yaml --vary KEY=V1,V2,...\n"
    "                    error against run time over combinations of case keys\n"
    "\n"
    "options:\n"
    "  --help            help for a command (tetcontact run --help)\n"
    "  --version         print the version\n"
    "\n"
    "exit codes: 0 success, 1 run failure (summary.json says why), 2 bad input\n";

const char* k_run_usage =
    "usage: tetcontact run CASE.yaml [--out DIR] [--force] [--set KEY=VALUE]... [--quiet] "
    "[--check]\n"
    "\n"
    "Runs the case and writes into DIR (default results/<case name>):\n"
    "  case.pvd, frame_NNNN.vtu   ParaView series (open case.pvd)\n"
    "  history.csv                energies, momentum and stage timings per step\n"
    "  summary.json               the run's summary (status, balance, bodies, timings)\n"
    "\n"
    "  --out DIR          output directory; created; a non-empty one is refused\n"
    "  --force            reuse a non-empty DIR, replacing the files of a previous run\n"
    "  --set KEY=VALUE    override a case key, e.g. --set solver.cfl=0.3 or\n"
    "                     --set bodies.0.velocity=[0,0,-100] (repeatable; VALUE is YAML)\n"
    "  --quiet            no progress and no final table\n"
    "  --check            exit 1 when the run misses a reference value the case declares\n"
    "                     (its `reference:` section; summary.json lists them in any case)\n"
    "\n"
    "Progress goes to stderr (a bar on a terminal, periodic lines otherwise), the final\n"
    "table to stdout. Exit codes: 0 success, 1 run failure, 2 bad input (nothing written).\n";

const char* k_sweep_usage =
    "usage: tetcontact sweep CASE.yaml --vary KEY=V1,V2,... [--vary KEY2=...]\n"
    "                        [--reference analytic|finest|SUMMARY.json] [--out DIR] [--force]\n"
    "                        [--set KEY=VALUE]... [--quiet]\n"
    "\n"
    "Runs the case once per combination of the varied keys (the last varying fastest; a\n"
    "value may be a YAML list, e.g. --vary bodies.0.mesh.box.cells=[20,2,2],[40,4,4]; keys\n"
    "joined by + take the same values, e.g. --vary bodies.0.mesh.box.cells+bodies.1.mesh.box.\n"
    "cells=[20,2,2],[40,4,4]) and\n"
    "writes DIR/sweep.csv (default DIR results/<case name>-sweep): per run the varied values,\n"
    "status, wall_seconds, steps, tets, error, the error of each declared reference (analytic),\n"
    "momentum_error, energy_balance_max, penetration_depth_over_h and crossings (largest of 21\n"
    "measures over the run; empty for one body). `error` is against --reference:\n"
    "  analytic       the largest relative error of the case's declared references (default)\n"
    "  finest         the largest relative difference of the bodies' velocities and extents\n"
    "                 and the contact's duration and peak force from the run with the most\n"
    "                 tets (then smallest cfl, then most passes, then the later), each\n"
    "                 relative to the largest value of its kind\n"
    "  SUMMARY.json   the same figures from an earlier run's summary\n"
    "A table goes to stdout, one progress line per run to stderr. Plot with\n"
    "tools/plot_sweep.py DIR/sweep.csv. Exit codes: 0, 1 a run failed (its row says so), 2 bad\n"
    "input (nothing run).\n";

const char* k_check_usage =
    "usage: tetcontact check CASE.yaml [--set KEY=VALUE]...\n"
    "\n"
    "Validates the case file, builds its meshes and computes the first time step; prints\n"
    "one line on success. Exit codes: 0 valid, 2 bad input.\n";

const char* k_stress_usage =
    "usage: tetcontact stress [--seed S] [--count N] [--scenes DIR | --no-scenes] [--json]\n"
    "\n"
    "Generates N queries (default 1000) per degenerate family (parallel, collinear and\n"
    "crossing edges, zero-length edges, edges a few ulps from parallel, coplanar vertex-face,\n"
    "vertex on a face's edge or corner, collapsed faces), each with its answer known by\n"
    "construction and placed by an exact transformation (offsets, axis permutations and\n"
    "signs, scales 2^-30 to 2^30, time reversal, primitive order). Compares the exact CCD\n"
    "with every answer and prints, per family, queries, true collisions, disagreements and\n"
    "mean time (and, for vertex-face, the disagreements of the floating-point swept test of\n"
    "vertex_face.hpp, for comparison). Then runs the micro-scenes, small cases that put\n"
    "bodies in degenerate contact (coincident faces, an edge in a face, a vertex on an\n"
    "edge, one touching point), from DIR (default: data/cases/micro of the source tree),\n"
    "and prints per scene the steps, status, momentum error, energy balance and\n"
    "penetration; a scene passes with no NaN, no inverted element and momentum conserved\n"
    "to 1e-12. --json: one object with `families`, `disagreements`, `scenes` and\n"
    "`scenes_failed`.\n"
    "Exit codes: 0 no disagreement and every scene passed, 1 otherwise, 2 bad usage or input.\n";

const char* k_profile_usage =
    "usage: tetcontact profile CASE.yaml [--broadphase NAME|all] [--steps N] [--json] [--set "
    "K=V]...\n"
    "       tetcontact profile --frames A.ply B.ply [--broadphase NAME|all] [--margin M] [--json]\n"
    "\n"
    "Case mode: runs N steps (default 100) of the case with contact on, once per broadphase\n"
    "method, and prints per method: surface primitives, candidate node-face pairs and confirmed\n"
    "contacts per step, pruning ratios (candidates over all cross-body pairs, contacts over\n"
    "candidates), broadphase build and query time per step, step time, and the broadphase's\n"
    "share of the step.\n"
    "Frames mode: a triangle surface at the start (A) and end (B) of a step (same connectivity,\n"
    "PLY ascii or binary); counts the edge-edge and vertex-face pairs whose swept boxes,\n"
    "inflated by M (default 0), overlap (touching counts; pairs sharing a vertex are skipped).\n"
    "Methods: fcl_tree, fcl_sap, grid, sweep, brute_force (all: every one; brute_force only\n"
    "where it is affordable). --json: stdout is one JSON array, an object per method.\n";

int usage_error(const std::string& msg, const char* usage) {
  std::cerr << "tetcontact: " << msg << "\n\n" << usage;
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) return usage_error("no command given", k_usage);
  const std::string cmd = args[0];
  if (cmd == "--help" || cmd == "-h" || cmd == "help") {
    std::cout << k_usage;
    return 0;
  }
  if (cmd == "--version") {
    std::cout << "tetcontact " << TETCONTACT_VERSION << "\n";
    return 0;
  }
  if (cmd == "ccd") {
    tc::CcdOptions c;
    for (std::size_t i = 1; i < args.size(); ++i) {
      const std::string& a = args[i];
      if (a == "--help" || a == "-h") {
        std::cout
            << "usage: tetcontact ccd FILE [--toi] [--fcl] [--json] [--quiet]\n\n"
               "One query a line: TYPE [GT] 24 coordinates (ee: a0 a1 b0 b1 at t=0, then at\n"
               "t=1; vf: v f0 f1 f2 at t=0, then at t=1). Prints 0/1 per query, and with\n"
               "ground truth the false positives, false negatives and mean time per type.\n"
               "--toi: after each 1, the earliest time of impact in [0, 1] (exact, rounded\n"
               "down to a double; the mean time then includes finding it).\n"
               "--fcl: also FCL 0.7's cubic CCD on the same queries (its answers, errors and\n"
               "time; JSON: an \"fcl\" object per type). Times are batch means over >= 0.2 s.\n"
               "--json: one object {\"ee\": {...}, \"vf\": {...}}. Answers are exact.\n";
        return 0;
      } else if (a == "--json") {
        c.json = true;
      } else if (a == "--quiet") {
        c.quiet = true;
      } else if (a == "--toi") {
        c.toi = true;
      } else if (a == "--fcl") {
        c.fcl = true;
      } else if (!a.empty() && a[0] == '-') {
        return usage_error("unknown option '" + a + "'", k_usage);
      } else {
        c.file = a;
      }
    }
    if (c.file.empty()) return usage_error("no query file given", k_usage);
    return tc::ccd_command(c);
  }
  if (cmd == "stress") {
    tc::StressOptions st;
    for (std::size_t i = 1; i < args.size(); ++i) {
      const std::string& a = args[i];
      const std::string* v = i + 1 < args.size() ? &args[i + 1] : nullptr;
      if (a == "--help" || a == "-h") {
        std::cout << k_stress_usage;
        return 0;
      } else if (a == "--json") {
        st.json = true;
      } else if (a == "--no-scenes") {
        st.scenes_dir.clear();
      } else if (a == "--scenes") {
        if (!v) return usage_error("--scenes needs a directory", k_stress_usage);
        st.scenes_dir = *v;
        ++i;
      } else if (a == "--seed" || a == "--count") {
        char* end = nullptr;
        const long n = v ? std::strtol(v->c_str(), &end, 10) : -1;
        if (!v || *end || n < (a == "--seed" ? 0 : 1) || n > 100000000)
          return usage_error(a + " needs a whole number" + (a == "--seed" ? " >= 0" : " >= 1"),
                             k_stress_usage);
        if (a == "--seed")
          st.seed = static_cast<std::uint64_t>(n);
        else
          st.count = static_cast<int>(n);
        ++i;
      } else {
        return usage_error("unknown argument '" + a + "'", k_stress_usage);
      }
    }
    try {
      return tc::stress_command(st);
    } catch (const std::exception& e) {  // a missing or bad micro-scene case
      std::cerr << "tetcontact: error: " << e.what() << "\n";
      return 2;
    }
  }
  if (cmd == "sweep") {
    tc::SweepOptions w;
    for (std::size_t i = 1; i < args.size(); ++i) {
      const std::string& a = args[i];
      const std::string* v = i + 1 < args.size() ? &args[i + 1] : nullptr;
      if (a == "--help" || a == "-h") {
        std::cout << k_sweep_usage;
        return 0;
      } else if (a == "--vary") {
        if (!v || v->find('=') == std::string::npos || v->find('=') == 0 ||
            v->find('=') + 1 == v->size())
          return usage_error("--vary needs KEY=V1,V2,...", k_sweep_usage);
        const std::size_t eq = v->find('=');
        w.vary.emplace_back(v->substr(0, eq), tc::split_values(v->substr(eq + 1)));
        ++i;
      } else if (a == "--reference" || a == "--out" || a == "--set") {
        if (!v) return usage_error(a + " needs a value", k_sweep_usage);
        (a == "--reference" ? w.reference
         : a == "--out"     ? w.out_dir
                            : w.overrides.emplace_back()) = *v;
        ++i;
      } else if (a == "--force") {
        w.force = true;
      } else if (a == "--quiet") {
        w.quiet = true;
      } else if (!a.empty() && a[0] == '-') {
        return usage_error("unknown option '" + a + "'", k_sweep_usage);
      } else if (w.case_path.empty()) {
        w.case_path = a;
      } else {
        return usage_error("more than one case file given", k_sweep_usage);
      }
    }
    if (w.case_path.empty()) return usage_error("no case file given", k_sweep_usage);
    if (w.vary.empty()) return usage_error("give at least one --vary KEY=V1,V2,...", k_sweep_usage);
    try {
      return tc::sweep_command(w);
    } catch (const std::exception& e) {
      std::cerr << "tetcontact: internal error: " << e.what() << "\n";
      return 1;
    }
  }
  if (cmd == "profile") {
    tc::ProfileOptions p;
    for (std::size_t i = 1; i < args.size(); ++i) {
      const std::string& a = args[i];
      const auto next = [&]() -> const std::string* {
        return i + 1 < args.size() ? &args[++i] : nullptr;
      };
      const std::string* v = nullptr;
      if (a == "--help" || a == "-h") {
        std::cout << k_profile_usage;
        return 0;
      } else if (a == "--json") {
        p.json = true;
      } else if (a == "--broadphase") {
        if (!(v = next())) return usage_error("--broadphase needs a method", k_profile_usage);
        p.method = *v;
      } else if (a == "--steps") {
        if (!(v = next())) return usage_error("--steps needs a number", k_profile_usage);
        p.steps = std::atol(v->c_str());
        if (p.steps < 1) return usage_error("--steps must be at least 1", k_profile_usage);
      } else if (a == "--margin") {
        if (!(v = next())) return usage_error("--margin needs a length", k_profile_usage);
        char* end = nullptr;
        p.margin = std::strtod(v->c_str(), &end);
        if (*end || p.margin < 0)
          return usage_error("--margin must be a length >= 0", k_profile_usage);
      } else if (a == "--frames") {
        const std::string* f1 = next();
        const std::string* f2 = next();
        if (!f1 || !f2) return usage_error("--frames needs two PLY files", k_profile_usage);
        p.frames = {*f1, *f2};
      } else if (a == "--set") {
        if (!(v = next())) return usage_error("--set needs KEY=VALUE", k_profile_usage);
        p.overrides.push_back(*v);
      } else if (!a.empty() && a[0] == '-') {
        return usage_error("unknown option '" + a + "'", k_profile_usage);
      } else if (p.case_path.empty()) {
        p.case_path = a;
      } else {
        return usage_error("more than one case file given", k_profile_usage);
      }
    }
    if (p.case_path.empty() == p.frames.empty())
      return usage_error("give a case file or --frames A.ply B.ply", k_profile_usage);
    try {
      return tc::profile_command(p);
    } catch (const std::exception& e) {
      std::cerr << "tetcontact: internal error: " << e.what() << "\n";
      return 1;
    }
  }
  if (cmd != "run" && cmd != "check") return usage_error("unknown command '" + cmd + "'", k_usage);
  const char* usage = cmd == "run" ? k_run_usage : k_check_usage;

  tc::RunOptions o;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&](const char* flag) -> const std::string* {
      if (i + 1 >= args.size()) return nullptr;
      (void)flag;
      return &args[++i];
    };
    if (a == "--help" || a == "-h") {
      std::cout << usage;
      return 0;
    } else if (a == "--set") {
      const std::string* v = value("--set");
      if (!v) return usage_error("--set needs KEY=VALUE", usage);
      o.overrides.push_back(*v);
    } else if (a.rfind("--set=", 0) == 0) {
      o.overrides.push_back(a.substr(6));
    } else if (cmd == "run" && a == "--out") {
      const std::string* v = value("--out");
      if (!v) return usage_error("--out needs a directory", usage);
      o.out_dir = *v;
    } else if (cmd == "run" && a.rfind("--out=", 0) == 0) {
      o.out_dir = a.substr(6);
    } else if (cmd == "run" && a == "--force") {
      o.force = true;
    } else if (cmd == "run" && a == "--quiet") {
      o.quiet = true;
    } else if (cmd == "run" && a == "--check") {
      o.check = true;
    } else if (!a.empty() && a[0] == '-') {
      return usage_error("unknown option '" + a + "'", usage);
    } else if (o.case_path.empty()) {
      o.case_path = a;
    } else {
      return usage_error("more than one case file given", usage);
    }
  }
  if (o.case_path.empty()) return usage_error("no case file given", usage);
  try {
    return cmd == "run" ? tc::run_case(o) : tc::check_case(o);
  } catch (const std::exception& e) {
    std::cerr << "tetcontact: internal error: " << e.what() << "\n";
    return 1;
  }
}
