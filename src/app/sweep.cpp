#include "tetcontact/app/sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "tetcontact/app/setup.hpp"
#include "tetcontact/diagnostics/balance.hpp"
#include "tetcontact/diagnostics/penetration.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/io/files.hpp"
#include "tetcontact/io/json.hpp"
#include "tetcontact/solver/run_loop.hpp"
#include "tetcontact/solver/simulation.hpp"

namespace tc {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"") == std::string::npos) return s;
  std::string q = "\"";
  for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

std::vector<std::string> split_values(const std::string& list) {
  std::vector<std::string> out(1);
  int depth = 0;
  for (char ch : list) {
    if (ch == '[' || ch == '{') ++depth;
    if (ch == ']' || ch == '}') --depth;
    if (ch == ',' && depth == 0)
      out.emplace_back();
    else
      out.back() += ch;
  }
  return out;
}

namespace {

// "a+b+c": keys that take the same value in every run (e.g. both bodies' meshes).
std::vector<std::string> tied_keys(const std::string& keys) {
  std::vector<std::string> out(1);
  for (char ch : keys)
    if (ch == '+')
      out.emplace_back();
    else
      out.back() += ch;
  return out;
}

// Figures of a run that a reference run can be compared with: each body's velocity and
// bounding-box extent per axis, the contact's duration and largest force.
using Figures = std::map<std::string, double>;

Figures comparable_figures(const Simulation& sim) {
  Figures f;
  for (const BodyStats& b : body_stats(sim.model(), sim.state()))
    for (int d = 0; d < 3; ++d) {
      f["velocity:" + b.name + ":" + "xyz"[d]] = b.velocity[d];
      f["extent:" + b.name + ":" + "xyz"[d]] = b.bbox_max[d] - b.bbox_min[d];
    }
  if (sim.has_contact() && sim.contact_totals().first_time >= 0) {
    f["contact_duration"] = sim.contact_totals().last_time - sim.contact_totals().first_time;
    f["contact_max_force"] = sim.contact_totals().max_force;
  }
  return f;
}

// The same figures from a run's summary.json; a missing key is an error naming it.
Figures summary_figures(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw CaseError(path + ": cannot read the reference summary");
  Figures f;
  try {
    const Json s = Json::parse(in);
    if (!s.contains("bodies"))
      throw CaseError(path + ": not a tetcontact summary.json (no 'bodies')");
    for (const Json& b : s.at("bodies")) {
      const std::string name = b.at("name").get<std::string>();
      for (int d = 0; d < 3; ++d) {
        f["velocity:" + name + ":" + "xyz"[d]] = b.at("velocity").at(d).get<double>();
        f["extent:" + name + ":" + "xyz"[d]] =
            b.at("bbox_max").at(d).get<double>() - b.at("bbox_min").at(d).get<double>();
      }
    }
    const Json& c = s.at("contact");
    if (!c.at("duration").is_null()) {
      f["contact_duration"] = c.at("duration").get<double>();
      f["contact_max_force"] = c.at("max_force").get<double>();
    }
  } catch (const Json::exception& e) {
    throw CaseError(path + ": cannot read the reference summary (" + e.what() + ")");
  }
  return f;
}

// Largest relative difference of the figures both have; each kind relative to the largest
// reference value of that kind (a body at rest has no velocity of its own to compare with).
double figures_error(const Figures& run, const Figures& ref) {
  std::map<std::string, double> scale;
  const auto kind = [](const std::string& k) { return k.substr(0, k.find(':')); };
  for (const auto& [k, v] : ref) scale[kind(k)] = std::max(scale[kind(k)], std::abs(v));
  double err = 0.0;
  for (const auto& [k, v] : ref) {
    const auto it = run.find(k);
    if (it == run.end() || scale[kind(k)] == 0.0) continue;
    err = std::max(err, std::abs(it->second - v) / scale[kind(k)]);
  }
  return err;
}

struct Row {
  std::vector<std::string> values;  // the varied values
  std::string status = "ok";
  double wall = 0.0;
  long steps = 0, tets = 0;
  double cfl = 0.0;
  int passes = 0;
  double momentum = 0.0, balance = 0.0, depth_over_h = NAN;
  long crossings = -1;
  std::vector<double> ref_error;  // per declared reference (analytic)
  Figures figures;
  double error = NAN;  // against the sweep's reference
};

std::string num(double v) {
  if (std::isnan(v)) return "";
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

}  // namespace

namespace {

// Every combination of the varied values, the last key varying fastest.
std::vector<std::vector<std::string>> combinations(const SweepOptions& o) {
  std::vector<std::vector<std::string>> combos{{}};
  for (const auto& [key, values] : o.vary) {
    std::vector<std::vector<std::string>> next;
    for (const auto& c : combos)
      for (const std::string& v : values) {
        next.push_back(c);
        next.back().push_back(v);
      }
    combos = std::move(next);
  }
  return combos;
}

// One run of the sweep: its figures, penetration measured at 20 times and at the end.
Row sweep_run(const Case& c, const std::vector<std::string>& values) {
  Row row;
  row.values = values;
  row.cfl = c.cfl;
  row.passes = c.contact ? c.contact_settings.passes : 0;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    Simulation sim(build_model(c), solver_settings(c));
    row.tets = sim.model().mesh.tet_count();
    std::unique_ptr<PenetrationProbe> probe;
    if (sim.model().mesh.bodies.size() >= 2)
      probe = std::make_unique<PenetrationProbe>(sim.model());
    double next = 0.0;
    const auto measure = [&] {
      const Penetration p = probe->measure(sim.state());
      row.depth_over_h =
          std::max(std::isnan(row.depth_over_h) ? 0.0 : row.depth_over_h, p.max_depth_over_h);
      row.crossings = std::max(row.crossings, p.crossings);
    };
    ReferenceRecorder references(c.references);
    RunHooks hooks;
    hooks.references = &references;
    hooks.each_step = [&](const Simulation& s) {
      if (probe && s.state().t >= next) {
        measure();
        next += c.end_time / 20.0;
      }
    };
    row.status = run_to_end(sim, hooks);
    if (probe && row.status == "ok") measure();
    row.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    row.steps = sim.state().step;
    row.momentum = momentum_error(sim.first_sample(), sim.last_sample());
    row.balance = sim.balance_error_max();
    row.figures = comparable_figures(sim);
    if (row.status == "ok")
      for (const ReferenceResult& ref :
           references.finish(sim.model(), sim.state(), sim.run_figures()))
        row.ref_error.push_back(ref.relative_error);
  } catch (const SetupError& e) {
    row.status = std::string("bad input: ") + e.what();
  }
  return row;
}

// The error of each run against the sweep's reference; the finest run is the one with the
// most tets, then the smallest cfl, then the most passes, then the later in the sweep.
void sweep_errors(std::vector<Row>& rows, const std::string& reference, const Figures& file) {
  std::size_t finest = 0;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    const Row &a = rows[r], &b = rows[finest];
    if (std::tie(a.tets, b.cfl, a.passes) >= std::tie(b.tets, a.cfl, b.passes)) finest = r;
  }
  for (Row& row : rows) {
    if (row.status != "ok") continue;
    if (reference == "analytic") {
      row.error = 0.0;
      for (double e : row.ref_error)
        if (!std::isnan(e)) row.error = std::max(row.error, std::abs(e));  // NaN: not judged
    } else {
      row.error = figures_error(row.figures, reference == "finest" ? rows[finest].figures : file);
    }
  }
}

std::string sweep_csv(const SweepOptions& o, const Case& c0, const std::vector<Row>& rows) {
  std::ostringstream csv;
  for (const auto& [key, values] : o.vary) csv << csv_field(key) << ',';
  csv << "status,wall_seconds,steps,tets,error";
  if (o.reference == "analytic")
    for (const ReferenceSpec& ref : c0.references) csv << ',' << csv_field("error:" + ref.name);
  csv << ",momentum_error,energy_balance_max,penetration_depth_over_h,crossings\n";
  for (const Row& row : rows) {
    for (const std::string& v : row.values) csv << csv_field(v) << ',';
    csv << csv_field(row.status) << ',' << num(row.wall) << ',' << row.steps << ',' << row.tets
        << ',' << num(row.error);
    if (o.reference == "analytic")
      for (std::size_t k = 0; k < c0.references.size(); ++k)
        csv << ',' << (k < row.ref_error.size() ? num(row.ref_error[k]) : "");
    csv << ',' << num(row.momentum) << ',' << num(row.balance) << ',' << num(row.depth_over_h)
        << ',' << (row.crossings >= 0 ? std::to_string(row.crossings) : "") << '\n';
  }
  return csv.str();
}

std::string sweep_table(const SweepOptions& o, const Case& c0, const std::vector<Row>& rows,
                        const std::string& dir) {
  std::ostringstream os;
  os << "sweep of " << c0.name << " (" << rows.size() << " runs; error against "
     << (o.reference == "analytic" ? "the case's references"
         : o.reference == "finest" ? "the finest run"
                                   : o.reference)
     << ")\n";
  for (const auto& [key, values] : o.vary) os << "  " << key;
  os << "  | wall s | steps | error | momentum | energy | depth/h | crossings | status\n";
  for (const Row& row : rows) {
    for (const std::string& v : row.values) os << "  " << v;
    os << "  | " << num(row.wall) << " | " << row.steps << " | " << num(row.error) << " | "
       << num(row.momentum) << " | " << num(row.balance) << " | " << num(row.depth_over_h) << " | "
       << (row.crossings >= 0 ? std::to_string(row.crossings) : "-") << " | " << row.status << "\n";
  }
  os << "written: " << dir << "/sweep.csv\n";
  return os.str();
}

}  // namespace

int sweep_command(const SweepOptions& o) {
  const std::vector<std::vector<std::string>> combos = combinations(o);
  // All cases are read (and so checked) before anything runs or is written.
  std::vector<Case> cases;
  Figures file_reference;
  try {
    for (const auto& c : combos) {
      std::vector<std::string> overrides = o.overrides;
      for (std::size_t k = 0; k < c.size(); ++k)
        for (const std::string& key : tied_keys(o.vary[k].first))
          overrides.push_back(key + "=" + c[k]);
      cases.push_back(load_case(o.case_path, overrides));
    }
    if (o.reference != "analytic" && o.reference != "finest")
      file_reference = summary_figures(o.reference);
    if (o.reference == "analytic" && cases.front().references.empty())
      throw CaseError(o.case_path +
                      ": the case declares no reference values; use --reference finest or FILE");
  } catch (const CaseError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
    return 2;
  }
  const std::string dir =
      o.out_dir.empty() ? "results/" + cases.front().name + "-sweep" : o.out_dir;
  try {
    prepare_output_dir(dir, o.force);
  } catch (const OutputError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
    return 2;
  }
  std::vector<Row> rows;
  int code = 0;
  for (std::size_t r = 0; r < cases.size(); ++r) {
    Row row = sweep_run(cases[r], combos[r]);
    if (row.status != "ok") code = 1;
    if (!o.quiet) {
      std::cerr << "sweep: run " << r + 1 << "/" << cases.size() << ":";
      for (std::size_t k = 0; k < row.values.size(); ++k)
        std::cerr << " " << o.vary[k].first << "=" << row.values[k];
      std::cerr << " — " << row.status << ", " << row.steps << " steps, " << num(row.wall)
                << " s\n";
    }
    rows.push_back(std::move(row));
  }
  sweep_errors(rows, o.reference, file_reference);
  write_file_atomic(dir + "/sweep.csv", sweep_csv(o, cases.front(), rows));
  std::cout << sweep_table(o, cases.front(), rows, dir);
  return code;
}

}  // namespace tc
