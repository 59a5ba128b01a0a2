#include "tetcontact/app/stress.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <random>
#include <stdexcept>

#include <unistd.h>

#include "tetcontact/app/float_ccd.hpp"
#include "tetcontact/app/setup.hpp"
#include "tetcontact/app/summary.hpp"
#include "tetcontact/diagnostics/balance.hpp"
#include "tetcontact/diagnostics/penetration.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/io/files.hpp"
#include "tetcontact/io/json.hpp"
#include "tetcontact/narrowphase/exact_ccd.hpp"
#include "tetcontact/solver/run_loop.hpp"
#include "tetcontact/solver/simulation.hpp"

namespace tc {
namespace {

using Rng = std::mt19937_64;

int ri(Rng& rng, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo, hi)(rng);
}

bool between(long v, long a, long b) {
  return std::min(a, b) <= v && v <= std::max(a, b);
}

// --- Exact 2-D integer predicates (the oracle of the coplanar family) ----------------------

struct I2 {
  long x, y;
};
long orient(I2 a, I2 b, I2 c) {
  const long o = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  return (o > 0) - (o < 0);
}
bool on_segment(I2 p, I2 a, I2 b) {
  return orient(a, b, p) == 0 && between(p.x, a.x, b.x) && between(p.y, a.y, b.y);
}
// Closed segments [p, q] and [a, b] meet (zero-length and collinear segments included).
bool segments_meet(I2 p, I2 q, I2 a, I2 b) {
  const long d1 = orient(a, b, p), d2 = orient(a, b, q), d3 = orient(p, q, a), d4 = orient(p, q, b);
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  return on_segment(p, a, b) || on_segment(q, a, b) || on_segment(a, p, q) || on_segment(b, p, q);
}
// p in the closed, non-degenerate triangle (a, b, c); a degenerate one has no interior.
bool in_triangle(I2 p, I2 a, I2 b, I2 c) {
  const long o = orient(a, b, c);
  if (o == 0) return false;
  return orient(a, b, p) * o >= 0 && orient(b, c, p) * o >= 0 && orient(c, a, p) * o >= 0;
}

// --- Families: each returns one query with its constructed answer --------------------------

struct Family {
  const char* name;
  const char* description;
  bool integer;  // integer coordinates: an integer offset keeps them exact
  std::function<StressQuery(Rng&)> make;
};

StressQuery ee(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, const Vec3& A0,
               const Vec3& A1, const Vec3& B0, const Vec3& B1, bool truth) {
  return {true, {a0, a1, b0, b1, A0, A1, B0, B1}, truth};
}
StressQuery vf(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1,
               const Vec3& a1, const Vec3& b1, const Vec3& c1, bool truth) {
  return {false, {p0, a0, b0, c0, p1, a1, b1, c1}, truth};
}

std::vector<Family> families() {
  return {
      {"parallel-edges", "parallel edges, in one plane or in parallel planes, closing sideways",
       true,
       [](Rng& r) {
         // a = [0, L] on the x axis; b = [s, s + M] at height y = h(t), offset w in z. They
         // meet iff w = 0, h changes sign (or is 0) and the x ranges overlap.
         const int L = ri(r, 0, 4), s = ri(r, -5, 5), M = ri(r, 0, 4), h0 = ri(r, -2, 2),
                   h1 = ri(r, -2, 2), w = ri(r, 0, 3) == 0 ? ri(r, -1, 1) : 0;
         const Vec3 a0(0, 0, 0), a1(L, 0, 0);
         return ee(a0, a1, Vec3(s, h0, w), Vec3(s + M, h0, w), a0, a1, Vec3(s, h1, w),
                   Vec3(s + M, h1, w), w == 0 && h0 * h1 <= 0 && s <= L && s + M >= 0);
       }},
      {"collinear-edges", "edges on one line, one sliding along it (coplanar all step)", true,
       [](Rng& r) {
         // a = [p, p + L] static; b = [s(t), s(t) + M]: b sweeps [min s, max s + M].
         const int p = ri(r, -3, 3), L = ri(r, 0, 4), M = ri(r, 0, 4), s0 = ri(r, -8, 8),
                   s1 = ri(r, -8, 8);
         const Vec3 a0(p, 0, 0), a1(p + L, 0, 0);
         return ee(a0, a1, Vec3(s0, 0, 0), Vec3(s0 + M, 0, 0), a0, a1, Vec3(s1, 0, 0),
                   Vec3(s1 + M, 0, 0), std::min(s0, s1) <= p + L && std::max(s0, s1) + M >= p);
       }},
      {"crossing-edges", "perpendicular edges crossing, touching at t = 0 or 1, sharing endpoints",
       true,
       [](Rng& r) {
         // a on the x axis; b along y at x = bx, height z(t). They meet iff z changes sign
         // (or is 0) while bx lies in a's x range and 0 in b's y range.
         const int ax0 = ri(r, -3, 3), ax1 = ri(r, -3, 3), bx = ri(r, -4, 4), by0 = ri(r, -3, 3),
                   by1 = ri(r, -3, 3), z0 = ri(r, -2, 2), z1 = ri(r, -2, 2);
         const Vec3 a0(ax0, 0, 0), a1(ax1, 0, 0);
         return ee(a0, a1, Vec3(bx, by0, z0), Vec3(bx, by1, z0), a0, a1, Vec3(bx, by0, z1),
                   Vec3(bx, by1, z1),
                   z0 * z1 <= 0 && between(bx, ax0, ax1) && between(0, by0, by1));
       }},
      {"zero-length-edges", "a point-edge (and a point) passing an edge", true,
       [](Rng& r) {
         const int ax0 = ri(r, -3, 3), ax1 = ri(r, 0, 1) ? ax0 : ri(r, -3, 3), bx = ri(r, -3, 3),
                   by = ri(r, 0, 2) == 0 ? ri(r, -1, 1) : 0, z0 = ri(r, -2, 2), z1 = ri(r, -2, 2);
         const Vec3 a0(ax0, 0, 0), a1(ax1, 0, 0), b0(bx, by, z0), b1(bx, by, z1);
         return ee(a0, a1, b0, b0, a0, a1, b1, b1,
                   by == 0 && z0 * z1 <= 0 && between(bx, ax0, ax1));
       }},
      {"near-parallel-ulps", "edges a few ulps from parallel, meeting or missing by an ulp", false,
       [](Rng& r) {
         // a = [0, 1] on x; b from (0, h, e) to (1, h, e + d), d = k ulps of 1; h goes from 1
         // to −1 or 0, so b is in a's plane y = 0 only at one instant, where it meets a iff
         // e ≤ 0 ≤ e + d.
         const int k = ri(r, 1, 4), j = ri(r, -4 * k - 3, 3), h1 = ri(r, -1, 0);
         const double d = std::ldexp(k, -52), e = std::ldexp(j, -54);
         const Vec3 a0(0, 0, 0), a1(1, 0, 0);
         return ee(a0, a1, Vec3(0, 1, e), Vec3(1, 1, e + d), a0, a1, Vec3(0, h1, e),
                   Vec3(1, h1, e + d), j <= 0 && j + 4 * k >= 0);
       }},
      {"coplanar-vertex-face", "a vertex moving in the plane of a face (coplanar all step)", true,
       [](Rng& r) {
         I2 p0{ri(r, -4, 4), ri(r, -4, 4)}, p1{ri(r, -4, 4), ri(r, -4, 4)};
         I2 a{ri(r, -4, 4), ri(r, -4, 4)}, b{ri(r, -4, 4), ri(r, -4, 4)},
             c{ri(r, -4, 4), ri(r, -4, 4)};
         const bool truth = in_triangle(p0, a, b, c) || in_triangle(p1, a, b, c) ||
                            segments_meet(p0, p1, a, b) || segments_meet(p0, p1, b, c) ||
                            segments_meet(p0, p1, c, a);
         const auto v = [](I2 q) { return Vec3(q.x, q.y, 0); };
         return vf(v(p0), v(a), v(b), v(c), v(p1), v(a), v(b), v(c), truth);
       }},
      {"vertex-on-face-edge-vertex",
       "a vertex meeting a face in its interior, on an edge or at a corner, at t = 0, 1 or "
       "between",
       true,
       [](Rng& r) {
         // Triangle (0,0), (N,0), (0,N); relative height z(t) of the vertex above it, moved
         // either by the vertex or by the face.
         const int N = ri(r, 1, 4), x = ri(r, -1, 5), y = ri(r, -1, 5), z0 = ri(r, -2, 2),
                   z1 = ri(r, -2, 2);
         const bool truth = z0 * z1 <= 0 && x >= 0 && y >= 0 && x + y <= N;
         if (ri(r, 0, 1))
           return vf(Vec3(x, y, z0), Vec3(0, 0, 0), Vec3(N, 0, 0), Vec3(0, N, 0), Vec3(x, y, z1),
                     Vec3(0, 0, 0), Vec3(N, 0, 0), Vec3(0, N, 0), truth);
         return vf(Vec3(x, y, 0), Vec3(0, 0, -z0), Vec3(N, 0, -z0), Vec3(0, N, -z0), Vec3(x, y, 0),
                   Vec3(0, 0, -z1), Vec3(N, 0, -z1), Vec3(0, N, -z1), truth);
       }},
      {"degenerate-faces", "faces collapsed to a segment or a point, swept over a vertex", true,
       [](Rng& r) {
         // Face corners on the x axis at 0, m, n (m = n = 0: a point); the vertex (x, y)
         // falls through z = 0: it meets the face iff y = 0 and x lies in the corners' span.
         const bool point = ri(r, 0, 3) == 0;
         const int m = point ? 0 : ri(r, -3, 3), n = point ? 0 : ri(r, -3, 3), x = ri(r, -4, 4),
                   y = ri(r, 0, 2) == 0 ? ri(r, -1, 1) : 0, z0 = ri(r, -2, 2), z1 = ri(r, -2, 2);
         const long lo = std::min({0, m, n}), hi = std::max({0, m, n});
         const Vec3 a(0, 0, 0), b(m, 0, 0), c(n, 0, 0);
         return vf(Vec3(x, y, z0), a, b, c, Vec3(x, y, z1), a, b, c,
                   y == 0 && z0 * z1 <= 0 && lo <= x && x <= hi);
       }},
  };
}

// An exact transformation that keeps the answer: an integer offset (integer families), axis
// permutation and signs, a power-of-two scale, time reversal, primitive and endpoint order.
void transform(StressQuery& s, bool integer, Rng& r) {
  Vec3 offset(0, 0, 0);
  if (integer && ri(r, 0, 1))  // half of them: small coordinates stay small
    offset = Vec3(ri(r, -1000, 1000), ri(r, -1000, 1000), ri(r, -1000, 1000));
  static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  const int* perm = perms[ri(r, 0, 5)];
  const Vec3 sign(ri(r, 0, 1) ? 1 : -1, ri(r, 0, 1) ? 1 : -1, ri(r, 0, 1) ? 1 : -1);
  const int e = ri(r, -30, 30);  // 2^±30 ≈ 1e∓9 … 1e9
  for (Vec3& p : s.q) {
    const Vec3 u = p + offset;
    for (int d = 0; d < 3; ++d) p[d] = std::ldexp(sign[d] * u[perm[d]], e);
  }
  if (ri(r, 0, 1))
    for (int k = 0; k < 4; ++k) std::swap(s.q[k], s.q[4 + k]);
  if (s.edge_edge) {
    if (ri(r, 0, 1))
      for (int k : {0, 1, 4, 5}) std::swap(s.q[k], s.q[k + 2]);
    for (int first : {0, 2})
      if (ri(r, 0, 1)) {
        std::swap(s.q[first], s.q[first + 1]);
        std::swap(s.q[first + 4], s.q[first + 5]);
      }
  } else {
    const int rot = ri(r, 0, 2);
    std::rotate(s.q.begin() + 1, s.q.begin() + 1 + rot, s.q.begin() + 4);
    std::rotate(s.q.begin() + 5, s.q.begin() + 5 + rot, s.q.begin() + 8);
    if (ri(r, 0, 1)) {
      std::swap(s.q[2], s.q[3]);
      std::swap(s.q[6], s.q[7]);
    }
  }
}

}  // namespace

std::vector<StressFamily> stress_families(std::uint64_t seed, int count) {
  std::vector<StressFamily> out;
  const std::vector<Family> fams = families();
  for (std::size_t f = 0; f < fams.size(); ++f) {
    Rng rng(seed * 1000003ULL + f);
    StressFamily fam{fams[f].name, fams[f].description, {}};
    for (int i = 0; i < count; ++i) {
      StressQuery q = fams[f].make(rng);
      transform(q, fams[f].integer, rng);
      fam.queries.push_back(q);
    }
    out.push_back(std::move(fam));
  }
  return out;
}

std::string default_scenes_dir() {
  return data_dir() + "/cases/micro";
}

namespace {

// One scene through the solver, its penetration measured after every step.
SceneResult run_scene(const std::string& name, const std::string& file,
                      const std::vector<std::string>& overrides) {
  SceneResult r;
  r.name = name;
  const Case c = load_case(file, overrides);  // bad input is the caller's, not a scene's
  try {
    Simulation sim(build_model(c), solver_settings(c));
    PenetrationProbe probe(sim.model());
    RunHooks hooks;
    hooks.each_step = [&](const Simulation& s) {
      ++r.steps;
      keep_largest(r.penetration, probe.measure(s.state().x));
    };
    r.status = run_to_end(sim, hooks);  // "failed: ..." when the scene could not go on
    if (r.status == "ok") {
      r.momentum_error = momentum_error(sim.first_sample(), sim.last_sample());
      r.balance_error = sim.balance_error_max();
      r.impact_zones = sim.contact_totals().impact_zones;
      if (!std::isfinite(r.momentum_error) || !std::isfinite(r.balance_error))
        r.status = "non-finite balance";
    }
  } catch (const std::exception& e) {  // the setup refused the scene's model
    r.status = std::string("failed: ") + e.what();
  }
  ExpectFigures figures;
  figures.momentum_error = r.momentum_error;
  figures.energy_balance = r.balance_error;
  figures.penetration = r.penetration;
  r.expect = judge_expect(c.expect, figures);
  r.pass = r.status == "ok" && r.momentum_error <= 1e-12;
  for (const ExpectResult& e : r.expect) r.pass = r.pass && e.pass;
  return r;
}

double uniform(Rng& r, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(r);
}

std::string vec(const Vec3& v) {
  char b[128];
  std::snprintf(b, sizeof b, "[%.17g, %.17g, %.17g]", v.x(), v.y(), v.z());
  return b;
}

Vec3 unit(Rng& r) {
  for (;;) {
    const Vec3 v(uniform(r, -1, 1), uniform(r, -1, 1), uniform(r, -1, 1));
    if (v.squaredNorm() > 0.01 && v.squaredNorm() <= 1.0) return v.normalized();
  }
}

}  // namespace

std::vector<std::string> solver_scene_cases(std::uint64_t seed, int count) {
  std::vector<std::string> out;
  for (int i = 0; i < count; ++i) {
    Rng r(seed * 7919ULL + static_cast<std::uint64_t>(i));
    const int kind = i % 3;  // apart at an angle, touching face on face, touching and sliding
    const double speed = 100.0 * std::pow(70.0, uniform(r, 0, 1));  // 0.1 to 7 km/s
    const bool ball = kind == 0 && std::uniform_int_distribution<int>(0, 1)(r);
    std::string a_rot, b_rot, b_mesh, b_move;
    Vec3 velocity, spin = Vec3::Zero();
    double travel;  // m the projectile must close before contact, about
    if (kind == 0) {
      // Both turned at random; B on a random side, its bounding sphere 0 to 0.5 mm off A's.
      const Vec3 axis_a = unit(r), axis_b = unit(r), side = unit(r);
      a_rot = "{rotate: {axis: " + vec(axis_a) +
              ", degrees: " + std::to_string(uniform(r, 0, 180)) + "}}";
      b_rot = "{rotate: {axis: " + vec(axis_b) +
              ", degrees: " + std::to_string(uniform(r, 0, 180)) + "}}";
      const double ra = 0.005 * std::sqrt(3.0), rb = ball ? 0.003 : 0.003 * std::sqrt(3.0);
      const double gap = uniform(r, 0, 5e-4);
      b_move = "{translate: " + vec((ra + rb + gap) * side) + "}";
      velocity = -speed * (side + 0.3 * unit(r)).normalized();
      spin = uniform(r, 0, 2e4) * unit(r);
      travel = ra + rb + gap - 0.006;
    } else {
      // A axis-aligned, B on its top face (z = 0.005, exactly), turned about z, shifted.
      a_rot = "{translate: [0, 0, 0]}";
      b_rot = "{rotate: {axis: [0, 0, 1], degrees: " + std::to_string(uniform(r, 0, 90)) + "}}";
      const double dx = std::ldexp(std::floor(uniform(r, -16, 16)), -13);  // dyadic: exact
      const double dy = std::ldexp(std::floor(uniform(r, -16, 16)), -13);
      b_move = "{translate: " + vec(Vec3(dx, dy, 0.008)) + "}";
      const Vec3 slide(uniform(r, -1, 1), uniform(r, -1, 1), 0);
      velocity = kind == 1 ? Vec3(speed * (0.3 * slide + Vec3(0, 0, -1)))
                           : Vec3(speed * (slide.normalized() + Vec3(0, 0, -0.05)));
      travel = 0.0;
    }
    b_mesh = ball ? "{sphere: {radius: 0.003, cells_across: 4}}"
                  : "{box: {size: [0.006, 0.006, 0.006], cells: [2, 2, 2]}}";
    // Long enough to close the gap and press 1.5 mm on, at most 2e-4 s.
    const double end = std::min(2e-4, (std::max(travel, 0.0) + 1.5e-3) / speed);
    char name[64];
    std::snprintf(name, sizeof name, "scene-%04d-%s", i,
                  kind == 0   ? "apart"
                  : kind == 1 ? "touching"
                              : "sliding");
    std::string text;
    text += "name: " + std::string(name) + "\n";
    char end_time[64];
    std::snprintf(end_time, sizeof end_time, "end_time: %.17g\n", end);
    text += end_time;
    text += "solver: {max_steps: 2000}\n";  // a scene that crushes its cells stops there
    text += "materials:\n  al: {from: al6061-t6}\n";
    text += "bodies:\n";
    text += "  - name: target\n    material: al\n";
    text += "    mesh: {box: {size: [0.01, 0.01, 0.01], cells: [2, 2, 2]}}\n";
    text += "    transform: [" + a_rot + "]\n";
    text += "  - name: projectile\n    material: al\n";
    text += "    mesh: " + b_mesh + "\n";
    text += "    transform: [" + b_rot + ", " + b_move + "]\n";
    text += "    velocity: " + vec(velocity) + "\n";
    text += "    angular_velocity: " + vec(spin) + "\n";
    text += "contact: {enabled: true, edge_edge: true, verify: true}\n";
    out.push_back(text);
  }
  return out;
}

std::vector<SceneResult> run_solver_scenes(std::uint64_t seed, int count,
                                           const std::vector<std::string>& overrides) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("tetcontact-scenes-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::vector<SceneResult> out;
  const std::vector<std::string> cases = solver_scene_cases(seed, count);
  const std::string file = (dir / "scene.yaml").string();
  for (const std::string& text : cases) {
    write_file_atomic(file, text);
    const std::string name = text.substr(6, text.find('\n') - 6);  // "name: scene-…"
    try {
      out.push_back(run_scene(name, file, overrides));
    } catch (const std::exception& e) {  // a scene the setup refuses (it overlaps at t = 0)
      SceneResult r;
      r.name = name;
      r.status = std::string("refused: ") + e.what();
      out.push_back(r);
    }
  }
  fs::remove_all(dir);
  return out;
}

std::vector<SceneResult> run_micro_scenes(const std::string& dir,
                                          const std::vector<std::string>& overrides) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  if (fs::is_directory(dir))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".yaml") files.push_back(e.path());
  if (files.empty()) throw std::runtime_error(dir + ": no micro-scene case (*.yaml) found");
  std::sort(files.begin(), files.end());
  std::vector<SceneResult> out;
  for (const fs::path& f : files)
    out.push_back(run_scene(f.stem().string(), f.string(), overrides));
  return out;
}

namespace {

// The degenerate CCD families against their constructed answers (j["families"]): the number of
// disagreements of the exact CCD.
long stress_families_report(const StressOptions& o, Json& j) {
  long total = 0;
  Json& arr = j["families"] = Json::array();
  if (!o.json)
    std::printf("%-28s %4s %8s %6s %14s %18s %10s\n", "family", "type", "queries", "true",
                "disagreements", "float disagreements", "mean us");
  for (const StressFamily& fam : stress_families(o.seed, o.count)) {
    long truths = 0, wrong = 0, float_wrong = 0;
    double seconds = 0;
    const bool is_ee = !fam.queries.empty() && fam.queries.front().edge_edge;
    for (const StressQuery& s : fam.queries) {
      const auto t0 = std::chrono::steady_clock::now();
      const bool hit = s.edge_edge ? exact_edge_edge_ccd(s.q) : exact_vertex_face_ccd(s.q);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      truths += s.truth;
      wrong += hit != s.truth;
      if (!s.edge_edge) {
        const auto& q = s.q;
        const bool fp = vertex_face_ccd(q[0], q[1], q[2], q[3], q[4], q[5], q[6], q[7]).has_value();
        float_wrong += fp != s.truth;
      }
    }
    total += wrong;
    const long n = static_cast<long>(fam.queries.size());
    const double mean_ns = n ? 1e9 * seconds / n : 0.0;
    Json x = Json::object();
    x["name"] = fam.name;
    x["description"] = fam.description;
    x["type"] = is_ee ? "ee" : "vf";
    x["queries"] = n;
    x["collisions"] = truths;
    x["disagreements"] = wrong;
    if (!is_ee) x["float_disagreements"] = float_wrong;
    x["mean_ns"] = mean_ns;
    arr.push_back(x);
    if (!o.json) {
      char fl[24] = "-";
      if (!is_ee) std::snprintf(fl, sizeof fl, "%ld", float_wrong);
      std::printf("%-28s %4s %8ld %6ld %14ld %18s %10.1f\n", fam.name.c_str(), is_ee ? "ee" : "vf",
                  n, truths, wrong, fl, mean_ns / 1e3);
    }
  }
  j["seed"] = static_cast<long>(o.seed);
  j["count"] = o.count;
  j["disagreements"] = total;
  if (!o.json)
    std::printf(
        "%ld disagreements with the constructed answers (exact CCD); float disagreements: the\n"
        "floating-point swept vertex-face test of app/float_ccd.hpp, for comparison\n",
        total);
  return total;
}

// The micro-scenes of `scenes_dir` through the solver (j["scenes"]): the number that failed.
long micro_scenes_report(const StressOptions& o, const std::string& scenes_dir, Json& j) {
  long failed = 0;
  {
    const std::vector<SceneResult> scenes = run_micro_scenes(scenes_dir, o.overrides);
    Json& js = j["scenes"] = Json::array();
    if (!o.json)
      std::printf("\n%-26s %6s %-8s %14s %14s %12s %12s %10s\n", "micro-scene", "steps", "status",
                  "momentum err", "energy bal.", "depth / h", "nodes inside", "crossings");
    for (const SceneResult& r : scenes) {
      failed += !r.pass;
      Json x = Json::object();
      x["name"] = r.name;
      x["steps"] = r.steps;
      x["status"] = r.status;
      x["momentum_error"] = r.momentum_error;
      x["balance_error"] = r.balance_error;
      x["max_depth_over_h"] = r.penetration.max_depth_over_h;
      x["nodes_inside"] = r.penetration.nodes_inside;
      x["crossings"] = r.penetration.crossings;
      x["max_crossing_depth"] = r.penetration.max_crossing_depth;
      std::string missed;
      for (const ExpectResult& e : r.expect)
        if (!e.pass) missed += " " + e.name;
      x["expect"] = expect_json(r.expect);
      x["pass"] = r.pass;
      js.push_back(x);
      if (!o.json)
        std::printf("%-26s %6ld %-8s %14.2e %14.2e %12.2e %12ld %10ld%s%s\n", r.name.c_str(),
                    r.steps, r.pass ? "ok" : "FAILED", r.momentum_error, r.balance_error,
                    r.penetration.max_depth_over_h, r.penetration.nodes_inside,
                    r.penetration.crossings, r.status == "ok" ? "" : ("  " + r.status).c_str(),
                    missed.empty() ? "" : ("  missed:" + missed).c_str());
    }
    if (!o.json)
      std::printf(
          "%ld of %zu micro-scenes failed (a pass: no NaN, no inverted element, momentum to "
          "1e-12, the scene's expect: bounds held at every step)\n",
          failed, scenes.size());
  }
  return failed;
}

// The generated whole-solver scenes (j["solver_scenes"]): the number with a crossing or a
// node inside after some step.
long solver_scenes_report(const StressOptions& o, Json& j) {
  long crossed = 0;
  {
    const std::vector<SceneResult> scenes = run_solver_scenes(o.seed, o.solver_scenes, o.overrides);
    long runs_failed = 0, zones = 0, with_zones = 0, max_crossings = 0, max_inside = 0;
    Json& js = j["solver_scenes"] = Json::object();
    Json list = Json::array();
    for (const SceneResult& r : scenes) {
      const bool bad = r.penetration.crossings > 0 || r.penetration.nodes_inside > 0;
      crossed += bad;
      runs_failed += r.status != "ok";
      zones += r.impact_zones;
      with_zones += r.impact_zones > 0;
      max_crossings = std::max(max_crossings, r.penetration.crossings);
      max_inside = std::max(max_inside, r.penetration.nodes_inside);
      Json x = Json::object();
      x["name"] = r.name;
      x["steps"] = r.steps;
      x["status"] = r.status;
      x["crossings"] = r.penetration.crossings;
      x["nodes_inside"] = r.penetration.nodes_inside;
      x["max_depth"] = r.penetration.max_depth;
      x["momentum_error"] = r.momentum_error;
      x["balance_error"] = r.balance_error;
      x["impact_zones"] = r.impact_zones;
      list.push_back(x);
      if (!o.json && (bad || r.status != "ok"))
        std::printf("  %-24s %5ld steps  crossings %ld  nodes inside %ld  %s\n", r.name.c_str(),
                    r.steps, r.penetration.crossings, r.penetration.nodes_inside, r.status.c_str());
    }
    js["scenes"] = list;
    js["count"] = static_cast<long>(scenes.size());
    js["with_crossings"] = crossed;
    js["runs_failed"] = runs_failed;
    js["max_crossings"] = max_crossings;
    js["max_nodes_inside"] = max_inside;
    js["scenes_with_zones"] = with_zones;
    js["impact_zones"] = zones;
    if (!o.json)
      std::printf(
          "\n%zu generated solver scenes (apart at random angles, touching, sliding; 0.1 to 7 "
          "km/s): %ld with a crossing or a node inside (penetration after every step), %ld runs "
          "failed, %ld needed impact zones (%ld zones)\n",
          scenes.size(), crossed, runs_failed, with_zones, zones);
  }
  return crossed;
}

}  // namespace

int stress_command(const StressOptions& o) {
  const std::string scenes_dir = !o.scenes              ? std::string()
                                 : o.scenes_dir.empty() ? default_scenes_dir()
                                                        : o.scenes_dir;
  if (!scenes_dir.empty() && !std::filesystem::is_directory(scenes_dir))
    throw std::runtime_error(scenes_dir + ": micro-scene directory not found");
  Json j = Json::object();
  const long total = stress_families_report(o, j);
  const long failed = scenes_dir.empty() ? 0 : micro_scenes_report(o, scenes_dir, j);
  j["scenes_failed"] = failed;
  const long crossed = o.solver_scenes > 0 ? solver_scenes_report(o, j) : 0;
  if (o.json) std::cout << j.dump(2) << "\n";
  return total == 0 && failed == 0 && crossed == 0 ? 0 : 1;
}

}  // namespace tc
