// `tetcontact limit`: bracketing a ballistic limit by parallel runs of a case (limit.hpp).
//
// The search, for each value w of the second key: the criterion c(x) at both ends (they must
// differ), then, with J processes, the J points that cut the bracket [a, b] into J + 1 equal
// parts, all run at once; the bracket becomes the part where c first differs from c(a) (c is
// taken as monotone in x). It stops when b − a ≤ tolerance · max(|a|, |b|): each round divides
// the width by J + 1.
#include "tetcontact/app/limit.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

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

std::string self_exe() {
  std::vector<char> buf(4096);
  const ssize_t n = readlink("/proc/self/exe", buf.data(), buf.size() - 1);
  if (n <= 0) throw std::runtime_error("cannot find this program's path (/proc/self/exe)");
  return std::string(buf.data(), static_cast<std::size_t>(n));
}

// One run of the case: where it goes and what it found.
struct Run {
  double x = 0.0;
  std::string dir;
  std::vector<std::string> args;  // `run` and its options
  int value = -1;                 // the criterion: 1, 0; -1 unknown (failed)
  double wall = 0.0;
  bool reused = false;
  std::string error;
};

// Reads a finished run's summary: the criterion's measure, its wall time. False when there is
// no summary (the run has not finished).
bool read_run(Run& r, const std::string& measure_name) {
  const std::string path = r.dir + "/summary.json";
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

// Runs the runs that have no summary yet, `jobs` at a time, each as a child process writing its
// own folder (its output to run.log there).
void run_all(std::vector<Run*>& todo, int jobs, const std::string& exe,
             const std::string& measure_name) {
  std::map<pid_t, Run*> running;
  std::size_t next = 0;
  while (next < todo.size() || !running.empty()) {
    while (next < todo.size() && static_cast<int>(running.size()) < jobs) {
      Run* r = todo[next++];
      fs::create_directories(r->dir);
      std::vector<std::string> args{exe};
      args.insert(args.end(), r->args.begin(), r->args.end());
      const std::string log = r->dir + "/run.log";
      const pid_t pid = fork();
      if (pid == 0) {  // the child: its output to run.log, then the run
        const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int in = open("/dev/null", O_RDONLY);
        if (fd >= 0) dup2(fd, 1), dup2(fd, 2);
        if (in >= 0) dup2(in, 0);
        std::vector<char*> argv;
        for (std::string& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        execv(exe.c_str(), argv.data());
        _exit(127);
      }
      if (pid < 0) throw std::runtime_error("cannot start a run (fork)");
      running[pid] = r;
    }
    int status = 0;
    const pid_t done = waitpid(-1, &status, 0);
    if (done < 0) break;
    const auto it = running.find(done);
    if (it == running.end()) continue;
    Run* r = it->second;
    running.erase(it);
    if (!read_run(*r, measure_name))
      r->error = "the run wrote no summary (exit status " +
                 std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + "; see " + r->dir +
                 "/run.log)";
  }
}

struct Bracket {
  std::string vary_value;  // "" without --vary
  double a = 0.0, b = 0.0;
  int value_a = -1, value_b = -1;
  int runs = 0, reused = 0;
  double wall = 0.0;     // the search's elapsed time, s
  double run_sum = 0.0;  // the runs' own wall times added up (runs go side by side), s
  std::string status = "ok";
};

// One bracket: the value of `o.find` where the criterion flips, at the second key's value `w`
// ("" without --vary), by rounds of `jobs` runs at once between the ends, each run kept under
// DIR/runs/ and read back, not run again, when its summary is there.
Bracket search_bracket(const LimitOptions& o, const std::string& w, const std::string& dir,
                       const std::string& exe, int jobs, const std::string& measure_name) {
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
      r.dir = group + "/" + o.find + "=" + key;
      // Not quiet: run.log keeps the run's table, notes and warnings (no progress bar: the
      // log is not a terminal).
      r.args = {"run", o.case_path, "--out",           r.dir, "--force", "--threads",
                "1",   "--set",     o.find + "=" + key};
      if (!o.vary.empty()) r.args.insert(r.args.end(), {"--set", o.vary.front().first + "=" + w});
      for (const std::string& s : o.overrides) r.args.insert(r.args.end(), {"--set", s});
      if (read_run(r, measure_name)) {
        r.reused = true;
        ++br.reused;
      } else {
        todo.push_back(&r);
      }
      ++br.runs;
    }
    run_all(todo, jobs, exe, measure_name);
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
  std::string measure_name, case_name;
  try {
    for (const std::string& w : values)
      for (const double x : {o.lo, o.hi}) {
        std::vector<std::string> sets = o.overrides;
        sets.push_back(o.find + "=" + fmt(x));
        if (!o.vary.empty()) sets.push_back(o.vary.front().first + "=" + w);
        const Case c = load_case(o.case_path, sets);
        case_name = c.name;
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
  } catch (const CaseError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
    return 2;
  }
  const std::string dir = o.out_dir.empty() ? "results/" + case_name + "-limit" : o.out_dir;
  // A folder holding an earlier search's runs is resumed; any other non-empty one is refused.
  if (!fs::exists(dir + "/runs")) {
    try {
      prepare_output_dir(dir, false);
    } catch (const OutputError& e) {
      std::cerr << "tetcontact: error: " << e.what() << "\n";
      return 2;
    }
  }
  const std::string exe = self_exe();
  const int jobs = o.jobs > 0 ? o.jobs : std::max(1u, std::thread::hardware_concurrency());

  std::vector<Bracket> brackets;
  int code = 0;
  for (const std::string& w : values) {
    brackets.push_back(search_bracket(o, w, dir, exe, jobs, measure_name));
    if (brackets.back().status != "ok") code = 1;
  }

  std::ostringstream csv;
  csv << (o.vary.empty() ? "" : csv_field(o.vary.front().first) + ",")
      << "key,lo,hi,criterion_lo,criterion_hi,runs,reused,wall_seconds,run_seconds,status\n";
  for (const Bracket& br : brackets) {
    if (!o.vary.empty()) csv << csv_field(br.vary_value) << ',';
    csv << csv_field(o.find) << ',' << fmt(br.a) << ',' << fmt(br.b) << ',' << br.value_a << ','
        << br.value_b << ',' << br.runs << ',' << br.reused << ',' << fmt(br.wall) << ','
        << fmt(br.run_sum) << ',' << csv_field(br.status) << '\n';
  }
  write_file_atomic(dir + "/limit.csv", csv.str());
  std::cout << "written: " << dir << "/limit.csv\n";
  return code;
}

}  // namespace tc
