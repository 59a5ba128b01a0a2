// `tetcontact limit`: bracketing a ballistic limit by parallel runs of a case (limit.hpp).
//
// The search, for each value w of the second key: the criterion c(x) at both ends (they must
// differ), then, with J processes, the J points that cut the bracket [a, b] into J + 1 equal
// parts, all run at once; the bracket becomes the part where c first differs from c(a) (c is
// taken as monotone in x). It stops when b − a ≤ tolerance · max(|a|, |b|): each round divides
// the width by J + 1.
#include "tetcontact/app/limit.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>

#include "tetcontact/app/run.hpp"
#include "tetcontact/app/runs.hpp"
#include "tetcontact/app/sweep.hpp"
#include "tetcontact/diagnostics/reference.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/io/files.hpp"
#include "tetcontact/io/json.hpp"

namespace tc {
namespace {

namespace fs = std::filesystem;

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

// One run of the case: where it goes and what it found.
struct Run {
  double x = 0.0;
  ChildRun child;
  int value = -1;  // the criterion: 1, 0; -1 unknown (failed)
  double wall = 0.0;
  bool reused = false;
  std::string error;
};

// Reads a finished run's summary: the criterion's measure, its wall time. False when there is
// no summary (the run has not finished).
bool read_run(Run& r, const std::string& measure_name) {
  const std::string path = r.child.dir + "/summary.json";
  if (!fs::exists(path)) return false;
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  Json s;
  try {
    s = Json::parse(text.str());
  } catch (const std::exception&) {
    return false;  // a summary cut short: run again
  }
  r.wall = s.value("wall_seconds", 0.0);
  if (s.value("status", std::string()) != "ok") {
    r.error = "run failed: " + s.value("status", std::string("?"));
    return true;
  }
  if (s.contains("references"))
    for (const Json& ref : s["references"])
      if (ref.value("name", std::string()) == measure_name && ref["measured"].is_number()) {
        r.value = ref["measured"].get<double>() > 0.5 ? 1 : 0;
        return true;
      }
  r.error = "the summary has no measure '" + measure_name + "'";
  return true;
}

struct Bracket {
  std::string vary_value;  // "" without --vary
  double a = 0.0, b = 0.0;
  int value_a = -1, value_b = -1;
  int runs = 0, reused = 0;
  double wall = 0.0;     // the search's elapsed time, s
  double run_sum = 0.0;  // the runs' own wall times added up (runs go side by side), s
  std::string status = "ok";
  // The case's shield equation (Christiansen's) at the bracket's two ends: its critical
  // diameter (m), NaN when the case declares none.
  double equation_a = NAN, equation_b = NAN;
};

// The shield equation's critical diameter of the case at the overrides `sets` (NaN without one).
double equation_critical_diameter(const std::string& case_path,
                                  const std::vector<std::string>& sets) {
  const Case c = load_case(case_path, sets);
  return c.shield_equation.declared ? christiansen_critical_diameter(c.shield_equation.shot) : NAN;
}

// One bracket: the value of `o.find` where the criterion flips, at the second key's value `w`
// ("" without --vary), by rounds of `jobs` runs at once between the ends, each run kept under
// DIR/runs/ and read back, not run again, when its summary is there.
Bracket search_bracket(const LimitOptions& o, const std::string& w, const std::string& dir,
                       int jobs, const std::string& measure_name, const std::string& library,
                       const InputFiles& inputs) {
  Bracket br;
  br.vary_value = w;
  const auto started = std::chrono::steady_clock::now();
  const std::string group =
      dir + "/runs/" + (o.vary.empty() ? "all" : o.vary.front().first + "=" + w);
  std::map<std::string, Run> known;  // by the value's text
  const auto run_at = [&](const std::vector<double>& xs) {
    std::vector<Run*> todo;
    for (const double x : xs) {
      const std::string key = fmt(x);
      if (known.count(key)) continue;
      Run& r = known[key];
      r.x = x;
      // Every override of the run, in the order `run` applies them: the run's key.
      std::vector<std::string> sets = o.overrides;
      if (!o.vary.empty()) sets.push_back(o.vary.front().first + "=" + w);
      sets.push_back(o.find + "=" + key);
      r.child.key = run_key(o.case_path, sets, library);
      r.child.dir = group + "/" + run_folder_name(o.find + "=" + key, r.child.key);
      // Not quiet: run.log keeps the run's table, notes and warnings (no progress bar: the
      // log is not a terminal).
      r.child.args = {"run", o.case_path, "--out", r.child.dir, "--force", "--threads", "1"};
      for (const std::string& s : sets) r.child.args.insert(r.child.args.end(), {"--set", s});
      if (finished_run(r.child) && read_run(r, measure_name)) {
        r.reused = true;
        ++br.reused;
      } else {
        todo.push_back(&r);
      }
      ++br.runs;
    }
    std::vector<ChildRun*> children;
    for (Run* r : todo) children.push_back(&r->child);
    run_children(
        children, jobs,
        [&](ChildRun& c) {
          for (Run* r : todo)
            if (&r->child == &c && !read_run(*r, measure_name))
              r->error = "the run wrote no summary (exit status " + std::to_string(c.exit_code) +
                         "; see " + c.dir + "/run.log)";
        },
        &inputs);
  };
  const auto value = [&](double x) -> Run& { return known[fmt(x)]; };
  const auto failed = [&](const std::vector<double>& xs) {
    for (const double x : xs)
      if (value(x).value < 0) {
        br.status = "run at " + o.find + "=" + fmt(x) + ": " + value(x).error;
        return true;
      }
    return false;
  };
  double a = o.lo, b = o.hi;
  run_at({a, b});
  if (!failed({a, b})) {
    if (value(a).value == value(b).value) {
      br.status = std::string("no bracket: the criterion is ") +
                  (value(a).value ? "met" : "not met") + " at both ends";
    } else {
      while (b - a > o.tolerance * std::max(std::abs(a), std::abs(b))) {
        std::vector<double> xs;
        for (int i = 1; i <= jobs; ++i) xs.push_back(a + (b - a) * i / (jobs + 1));
        run_at(xs);
        if (failed(xs)) break;
        const int at_a = value(a).value;
        double na = xs.back(), nb = b;  // no flip inside: the last part
        for (std::size_t i = 0; i < xs.size(); ++i)
          if (value(xs[i]).value != at_a) {
            na = i == 0 ? a : xs[i - 1];
            nb = xs[i];
            break;
          }
        a = na;
        b = nb;
        if (!o.quiet)
          std::cerr << "limit: " << (w.empty() ? "" : o.vary.front().first + "=" + w + ": ")
                    << o.find << " in [" << fmt(a) << ", " << fmt(b) << "] after " << known.size()
                    << " runs\n";
      }
    }
  }
  br.a = a;
  br.b = b;
  br.value_a = value(a).value;
  br.value_b = value(b).value;
  for (const auto& [key, r] : known) br.run_sum += r.reused ? 0.0 : r.wall;
  br.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (!o.quiet)
    std::cerr << "limit: " << (w.empty() ? "" : o.vary.front().first + "=" + w + ": ") << o.find
              << " in [" << fmt(br.a) << ", " << fmt(br.b) << "]: " << br.status << " (" << br.runs
              << " runs, " << br.reused << " reused)\n";
  return br;
}

}  // namespace

int limit_command(const LimitOptions& o) {
  // Everything is checked before anything runs: the case at both ends (and each value of the
  // second key), the criterion's measure, the bracket.
  if (!(o.lo < o.hi)) {
    std::cerr << "tetcontact: error: --between LO HI needs LO < HI\n";
    return 2;
  }
  if (o.vary.size() > 1) {
    std::cerr << "tetcontact: error: --vary takes one key (the curve's abscissa)\n";
    return 2;
  }
  const std::string prefix = "perforated:";
  if (o.criterion.rfind(prefix, 0) != 0 || o.criterion.size() == prefix.size()) {
    std::cerr << "tetcontact: error: --criterion must be perforated:BODY, got '" << o.criterion
              << "'\n";
    return 2;
  }
  const std::string body = o.criterion.substr(prefix.size());
  const std::vector<std::string> values =
      o.vary.empty() ? std::vector<std::string>{""} : o.vary.front().second;
  std::string measure_name, case_name, library;
  InputFiles inputs;  // the text the runs' keys hold: an edit meanwhile stops the search
  try {
    if (fs::is_regular_file(o.case_path)) inputs.add(o.case_path);  // else load_case says why
    for (const std::string& w : values)
      for (const double x : {o.lo, o.hi}) {
        std::vector<std::string> sets = o.overrides;
        sets.push_back(o.find + "=" + fmt(x));
        if (!o.vary.empty()) sets.push_back(o.vary.front().first + "=" + w);
        const Case c = load_case(o.case_path, sets);
        case_name = c.name;
        library = c.material_library;  // a search varies numbers, not the library
        const auto it =
            std::find_if(c.references.begin(), c.references.end(), [&](const ReferenceSpec& r) {
              return r.measure == ReferenceSpec::Measure::perforated && r.body == body;
            });
        if (it == c.references.end())
          throw CaseError(o.case_path +
                          ": no `reference:` entry with measure: perforated and body: " + body +
                          " (the criterion " + o.criterion + ")");
        measure_name = it->name;
      }
    inputs.add(library);
  } catch (const CaseError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
    return 2;
  }
  if (o.check) {  // each case the search starts from, as `check` sees it; nothing runs
    int worst = 0;
    for (const std::string& w : values)
      for (const double x : {o.lo, o.hi}) {
        RunOptions r;
        r.case_path = o.case_path;
        r.overrides = o.overrides;
        r.overrides.push_back(o.find + "=" + fmt(x));
        if (!o.vary.empty()) r.overrides.push_back(o.vary.front().first + "=" + w);
        worst = std::max(worst, check_case(r));
      }
    if (worst == 0)
      std::cout << "limit: " << 2 * values.size()
                << " cases checked (each end of the bracket at each value): each makes a valid "
                   "case; nothing run\n";
    return worst;
  }
  const std::string dir = o.out_dir.empty() ? "results/" + case_name + "-limit" : o.out_dir;
  RunsFolderLock lock;
  try {
    lock = prepare_runs_folder(dir);
  } catch (const OutputError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
    return 2;
  }
  const int jobs = o.jobs > 0 ? o.jobs : std::max(1u, std::thread::hardware_concurrency());

  std::vector<Bracket> brackets;
  int code = 0;
  try {
    for (const std::string& w : values) {
      brackets.push_back(search_bracket(o, w, dir, jobs, measure_name, library, inputs));
      if (brackets.back().status != "ok") code = 1;
    }
    inputs.require_unchanged();  // an edit after the last run started
  } catch (const InputsChanged& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
    return 2;
  }

  // The shield equation beside the engine: its critical diameter for the shots at the
  // bracket's ends (the same at both when the search varies the diameter).
  bool equation = false;
  for (Bracket& br : brackets) {
    try {
      std::vector<std::string> sets = o.overrides;
      if (!o.vary.empty()) sets.push_back(o.vary.front().first + "=" + br.vary_value);
      sets.push_back(o.find + "=" + fmt(br.a));
      br.equation_a = equation_critical_diameter(o.case_path, sets);
      sets.back() = o.find + "=" + fmt(br.b);
      br.equation_b = equation_critical_diameter(o.case_path, sets);
      equation = equation || !std::isnan(br.equation_a);
      if (!std::isnan(br.equation_a) && !o.quiet)
        std::cout << "limit: "
                  << (o.vary.empty() ? "" : o.vary.front().first + "=" + br.vary_value + ": ")
                  << o.find << " in [" << fmt(br.a) << ", " << fmt(br.b)
                  << "]; Christiansen's equation: critical diameter " << fmt(br.equation_a)
                  << (br.equation_b == br.equation_a ? "" : " to " + fmt(br.equation_b)) << " m\n";
    } catch (const CaseError& e) {  // the brackets stand; the equation's column stays empty
      std::cerr << "limit: no equation beside " << br.vary_value << ": " << e.what() << "\n";
    }
  }
  std::ostringstream csv;
  csv << (o.vary.empty() ? "" : csv_field(o.vary.front().first) + ",")
      << "key,lo,hi,criterion_lo,criterion_hi,runs,reused,wall_seconds,run_seconds,status"
      << (equation ? ",equation_critical_diameter_lo,equation_critical_diameter_hi" : "") << "\n";
  for (const Bracket& br : brackets) {
    if (!o.vary.empty()) csv << csv_field(br.vary_value) << ',';
    csv << csv_field(o.find) << ',' << fmt(br.a) << ',' << fmt(br.b) << ',' << br.value_a << ','
        << br.value_b << ',' << br.runs << ',' << br.reused << ',' << fmt(br.wall) << ','
        << fmt(br.run_sum) << ',' << csv_field(br.status);
    const auto cell = [](double x) { return std::isnan(x) ? std::string() : fmt(x); };
    if (equation) csv << ',' << cell(br.equation_a) << ',' << cell(br.equation_b);
    csv << '\n';
  }
  write_file_atomic(dir + "/limit.csv", csv.str());
  std::cout << "written: " << dir << "/limit.csv\n";
  return code;
}

}  // namespace tc
