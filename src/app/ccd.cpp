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
#include "tetcontact/narrowphase/exact_ccd.hpp"

namespace tc {

int ccd_command(const CcdOptions& o) {
  std::ifstream in(o.file);
  if (!in) {
    std::cerr << "tetcontact: error: " << o.file << ": cannot open query file\n";
    return 2;
  }
  struct Tally {
    long queries = 0, collisions = 0, truth = 0, fp = 0, fn = 0;
    double seconds = 0.0;
  } ee, vf;
  bool have_truth = false;
  std::string line;
  long lineno = 0;
  std::string answers;
  while (std::getline(in, line)) {
    ++lineno;
    std::istringstream ss(line);
    std::string type;
    if (!(ss >> type)) continue;
    if (type != "ee" && type != "vf") {
      std::cerr << "tetcontact: error: " << o.file << ":" << lineno
                << ": query type must be ee or vf, got '" << type << "'\n";
      return 2;
    }
    std::vector<double> v;
    for (std::string tok; ss >> tok;) {
      char* end = nullptr;
      const double d = std::strtod(tok.c_str(), &end);
      if (*end) {
        std::cerr << "tetcontact: error: " << o.file << ":" << lineno << ": not a number: '" << tok
                  << "'\n";
        return 2;
      }
      v.push_back(d);
    }
    if (v.size() != 24 && v.size() != 25) {
      std::cerr << "tetcontact: error: " << o.file << ":" << lineno
                << ": expected 24 coordinates (25 with ground truth), got " << v.size() << "\n";
      return 2;
    }
    const bool truth_here = v.size() == 25;
    have_truth = have_truth || truth_here;
    const std::size_t off = truth_here ? 1 : 0;
    std::array<Vec3, 8> q;
    for (int k = 0; k < 8; ++k) q[k] = Vec3(v[off + 3 * k], v[off + 3 * k + 1], v[off + 3 * k + 2]);
    const auto t0 = std::chrono::steady_clock::now();
    std::optional<double> toi;
    bool hit;
    if (o.toi) {
      toi = type == "ee" ? exact_edge_edge_toi(q) : exact_vertex_face_toi(q);
      hit = toi.has_value();
    } else {
      hit = type == "ee" ? exact_edge_edge_ccd(q) : exact_vertex_face_ccd(q);
    }
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    Tally& t = type == "ee" ? ee : vf;
    ++t.queries;
    t.collisions += hit;
    t.seconds += sec;
    if (truth_here) {
      const bool gt = v[0] != 0.0;
      t.truth += gt;
      t.fp += hit && !gt;
      t.fn += !hit && gt;
    }
    if (!o.quiet && !o.json) {
      if (toi) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "1 %.17g\n", *toi);
        answers += buf;
      } else {
        answers += hit ? "1\n" : "0\n";
      }
    }
  }
  if (o.json) {
    Json j = Json::object();
    for (const auto& [name, t] : {std::pair<const char*, const Tally&>{"ee", ee}, {"vf", vf}}) {
      Json& x = j[name];
      x["queries"] = t.queries;
      x["collisions"] = t.collisions;
      if (have_truth) {
        x["false_positives"] = t.fp;
        x["false_negatives"] = t.fn;
        x["mean_ns"] = t.queries ? 1e9 * t.seconds / t.queries : 0.0;
      }
    }
    std::cout << j.dump();
    return 0;
  }
  std::cout << answers;
  if (have_truth)
    for (const auto& [name, t] : {std::pair<const char*, const Tally&>{"ee", ee}, {"vf", vf}})
      std::printf(
          "%s: %ld queries, %ld true collisions, %ld reported, %ld false positives, %ld false "
          "negatives, mean %.0f ns\n",
          name, t.queries, t.truth, t.collisions, t.fp, t.fn,
          t.queries ? 1e9 * t.seconds / t.queries : 0.0);
  return 0;
}

}  // namespace tc
