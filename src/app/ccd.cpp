#include "tetcontact/app/ccd.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <vector>

#include "tetcontact/io/json.hpp"
#include "tetcontact/narrowphase/cgal_ccd.hpp"
#include "tetcontact/narrowphase/exact_ccd.hpp"
#include "tetcontact/narrowphase/fcl_ccd.hpp"

namespace tc {
namespace {

struct Query {
  bool ee = false;
  std::array<Vec3, 8> q;
  int truth = -1;  // −1: none given
  bool hit = false;
  std::optional<double> toi;
};

struct Tally {
  long queries = 0, collisions = 0, truth = 0, fp = 0, fn = 0;
  double mean_ns = 0.0;
};

using Clock = std::chrono::steady_clock;

// Answers the queries of one type, timing them as a batch (a clock read per query would cost
// as much as FCL's whole test); short batches are repeated to at least 0.2 s.
template <class F>
std::vector<bool> answer_all(const std::vector<Query*>& qs, F&& answer, double& mean_ns) {
  std::vector<bool> out;
  out.reserve(qs.size());
  mean_ns = 0.0;
  if (qs.empty()) return out;
  const auto t0 = Clock::now();
  for (Query* q : qs) out.push_back(answer(*q));
  long rounds = 1;
  volatile long sink = 0;
  double sec = std::chrono::duration<double>(Clock::now() - t0).count();
  while (sec < 0.2) {
    long hits = 0;
    for (Query* q : qs) hits += answer(*q);
    sink = sink + hits;
    ++rounds;
    sec = std::chrono::duration<double>(Clock::now() - t0).count();
  }
  mean_ns = 1e9 * sec / (static_cast<double>(rounds) * static_cast<double>(qs.size()));
  return out;
}

Tally tally(const std::vector<Query*>& qs, const std::vector<bool>& answers) {
  Tally t;
  for (std::size_t i = 0; i < qs.size(); ++i) {
    ++t.queries;
    t.collisions += answers[i];
    if (qs[i]->truth >= 0) {
      const bool gt = qs[i]->truth != 0;
      t.truth += gt;
      t.fp += answers[i] && !gt;
      t.fn += !answers[i] && gt;
    }
  }
  return t;
}

// The queries of `file`, one a line: ee|vf, then [truth,] 24 coordinates. False, with the
// message said (file:line), on a malformed line.
bool read_queries(const std::string& file, std::vector<Query>& queries, bool& have_truth) {
  std::ifstream in(file);
  if (!in) {
    std::cerr << "tetcontact: error: " << file << ": cannot open query file\n";
    return false;
  }
  have_truth = false;
  std::string line;
  long lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    std::istringstream ss(line);
    std::string type;
    if (!(ss >> type)) continue;
    if (type != "ee" && type != "vf") {
      std::cerr << "tetcontact: error: " << file << ":" << lineno
                << ": query type must be ee or vf, got '" << type << "'\n";
      return false;
    }
    std::vector<double> v;
    for (std::string tok; ss >> tok;) {
      char* end = nullptr;
      const double d = std::strtod(tok.c_str(), &end);
      if (*end) {
        std::cerr << "tetcontact: error: " << file << ":" << lineno << ": not a number: '" << tok
                  << "'\n";
        return false;
      }
      v.push_back(d);
    }
    if (v.size() != 24 && v.size() != 25) {
      std::cerr << "tetcontact: error: " << file << ":" << lineno
                << ": expected 24 coordinates (25 with ground truth), got " << v.size() << "\n";
      return false;
    }
    Query q;
    q.ee = type == "ee";
    const std::size_t off = v.size() == 25 ? 1 : 0;
    if (off) q.truth = v[0] != 0.0;
    have_truth = have_truth || off;
    for (int k = 0; k < 8; ++k)
      q.q[k] = Vec3(v[off + 3 * k], v[off + 3 * k + 1], v[off + 3 * k + 2]);
    queries.push_back(q);
  }

  return true;
}

// Every answer of the fast path against the CGAL oracle, where it decides: x["cgal"] and a
// line of the table.
void confirm_with_cgal(const std::vector<Query*>& qs, const std::vector<bool>& ours, bool ee,
                       Json& x, std::string& table) {
  const char* name = ee ? "ee" : "vf";
  char buf[256];
  long agree = 0, disagree = 0, undecided = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < qs.size(); ++i) {
    const std::optional<bool> c =
        ee ? cgal_edge_edge_ccd(qs[i]->q) : cgal_vertex_face_ccd(qs[i]->q);
    if (!c)
      ++undecided;
    else if (*c == ours[i])
      ++agree;
    else
      ++disagree;
  }
  const double cns = 1e9 *
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() /
                     static_cast<double>(qs.size());
  Json& y = x["cgal"];
  y["agreements"] = agree;
  y["disagreements"] = disagree;
  y["undecided"] = undecided;
  y["mean_ns"] = cns;
  std::snprintf(buf, sizeof buf,
                "%s (CGAL oracle): %ld agree, %ld disagree, %ld undecided (coplanar all step, "
                "degenerate at the root), mean %.0f ns\n",
                name, agree, disagree, undecided, cns);
  table += buf;
}

// FCL's cubic CCD on the same queries: x["fcl"] and a line of the table.
void compare_with_fcl(std::vector<Query*>& qs, bool ee, bool have_truth, Json& x,
                      std::string& table) {
  const char* name = ee ? "ee" : "vf";
  char buf[256];
  double fns = 0.0;
  const std::vector<bool> fcl = answer_all(
      qs, [&](Query& q) { return ee ? fcl_edge_edge_ccd(q.q) : fcl_vertex_face_ccd(q.q); }, fns);
  Tally f = tally(qs, fcl);
  f.mean_ns = fns;
  Json& y = x["fcl"];
  y["collisions"] = f.collisions;
  if (have_truth) {
    y["false_positives"] = f.fp;
    y["false_negatives"] = f.fn;
  }
  y["mean_ns"] = f.mean_ns;
  if (have_truth)
    std::snprintf(buf, sizeof buf,
                  "%s (FCL 0.7 cubic): %ld reported, %ld false positives, %ld false "
                  "negatives, mean %.0f ns\n",
                  name, f.collisions, f.fp, f.fn, f.mean_ns);
  else  // no ground truth: no error counts to claim
    std::snprintf(buf, sizeof buf, "%s (FCL 0.7 cubic): %ld reported, mean %.0f ns\n", name,
                  f.collisions, f.mean_ns);
  table += buf;
}

}  // namespace

int ccd_command(const CcdOptions& o) {
  std::vector<Query> queries;
  bool have_truth = false;
  if (!read_queries(o.file, queries, have_truth)) return 2;

  // The answers (exact), timed per type, and FCL's beside them when asked.
  Json j = Json::object();
  std::string table;
  for (const bool ee : {true, false}) {
    std::vector<Query*> qs;
    for (Query& q : queries)
      if (q.ee == ee) qs.push_back(&q);
    double ns = 0.0;
    const std::vector<bool> ours = answer_all(
        qs,
        [&](Query& q) {
          if (!o.toi) return ee ? exact_edge_edge_ccd(q.q) : exact_vertex_face_ccd(q.q);
          const auto t = ee ? exact_edge_edge_toi(q.q) : exact_vertex_face_toi(q.q);
          q.toi = t;
          return t.has_value();
        },
        ns);
    for (std::size_t i = 0; i < qs.size(); ++i) qs[i]->hit = ours[i];
    Tally t = tally(qs, ours);
    t.mean_ns = ns;
    const char* name = ee ? "ee" : "vf";
    Json& x = j[name];
    x["queries"] = t.queries;
    x["collisions"] = t.collisions;
    x["mean_ns"] = t.mean_ns;
    if (have_truth) {
      x["false_positives"] = t.fp;
      x["false_negatives"] = t.fn;
    }
    char buf[256];
    if (have_truth)
      std::snprintf(buf, sizeof buf,
                    "%s: %ld queries, %ld true collisions, %ld reported, %ld false positives, %ld "
                    "false negatives, mean %.0f ns\n",
                    name, t.queries, t.truth, t.collisions, t.fp, t.fn, t.mean_ns);
    else  // no ground truth: the answers and the time
      std::snprintf(buf, sizeof buf, "%s: %ld queries, %ld reported, mean %.0f ns\n", name,
                    t.queries, t.collisions, t.mean_ns);
    table += buf;
    if (o.confirm == "cgal" && !qs.empty()) confirm_with_cgal(qs, ours, ee, x, table);
    if (o.fcl && !qs.empty()) compare_with_fcl(qs, ee, have_truth, x, table);
  }
  if (o.json) {
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  if (!o.quiet) {
    std::string answers;
    char buf[40];
    for (const Query& q : queries) {
      if (q.toi) {
        std::snprintf(buf, sizeof buf, "1 %.17g\n", *q.toi);
        answers += buf;
      } else {
        answers += q.hit ? "1\n" : "0\n";
      }
    }
    std::cout << answers;
  }
  std::cout << table;
  return 0;
}

}  // namespace tc
