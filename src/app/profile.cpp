#include "tetcontact/app/profile.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <mutex>

#include "tetcontact/app/setup.hpp"
#include "tetcontact/broadphase/broadphase.hpp"
#include "tetcontact/io/files.hpp"
#include "tetcontact/io/json.hpp"
#include "tetcontact/io/ply.hpp"
#include "tetcontact/narrowphase/exact_ccd.hpp"
#include "tetcontact/parallel/parallel.hpp"
#include "tetcontact/solver/run_loop.hpp"
#include "tetcontact/solver/simulation.hpp"

namespace tc {
namespace {

using Clock = std::chrono::steady_clock;

// Resident memory of this process, bytes (Linux /proc/self/statm; 0 where unreadable).
double resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  double pages = 0.0, resident = 0.0;
  if (!(statm >> pages >> resident)) return 0.0;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE));
}

std::vector<std::string> methods_for(const std::string& method, double pairs) {
  if (method != "all") {
    make_broadphase(method);  // throws for an unknown name
    return {method};
  }
  std::vector<std::string> out{"fcl_tree", "fcl_sap", "grid", "sweep"};
  // The oracle only where all pairs can be tested in reasonable time.
  if (pairs <= 2e8) out.push_back("brute_force");
  return out;
}

// The queries `--ccd-queries` records, from any thread.
std::mutex recorded_mutex;
std::vector<std::string> recorded;
void record_query(bool edge_edge, const std::array<Vec3, 8>& q) {
  std::string line = edge_edge ? "ee" : "vf";
  char buf[32];
  for (const Vec3& p : q)
    for (int d = 0; d < 3; ++d) {
      std::snprintf(buf, sizeof buf, " %a", p[d]);
      line += buf;
    }
  const std::lock_guard<std::mutex> lock(recorded_mutex);
  recorded.push_back(std::move(line));
}

int profile_case(const ProfileOptions& o) {
  Case base = load_case(o.case_path, o.overrides);
  Model probe = build_model(base);
  // All cross-body node–face pairs: the denominator of the pruning ratio.
  double all_pairs = 0.0, faces = 0.0, nodes = 0.0;
  for (const Surface& s : probe.surfaces) faces += s.faces.size(), nodes += s.nodes.size();
  for (const Surface& s : probe.surfaces) all_pairs += s.nodes.size() * (faces - s.faces.size());
  Json out = Json::array();
  if (!o.json)
    std::printf("%-12s %10s %11s %10s %10s %10s %9s %9s %9s %9s %9s %8s %8s %7s\n", "method",
                "primitives", "cand/step", "cont/step", "cand/all", "cont/cand", "build ms",
                "query ms", "step ms", "bp share", "contact", "islands", "largest", "B/tet");
  for (const std::string& m : methods_for(o.method, all_pairs)) {
    std::vector<std::string> ov = o.overrides;
    ov.push_back("contact.enabled=true");
    ov.push_back("contact.broadphase=" + m);
    const Case c = load_case(o.case_path, ov);
    // Memory of the run: what the process holds more once the model is built and the steps
    // have run (the model, the state, the kernels' and the contact modules' arrays).
    const double resident_before = resident_bytes();
    Simulation sim(build_model(c), solver_settings(c));
    const bool record = !o.ccd_queries.empty() && out.empty();  // the first method's steps
    if (record) set_ccd_observer(record_query);
    const auto t0 = Clock::now();
    long steps = 0;
    RunHooks hooks;
    hooks.each_step = [&](const Simulation&) { ++steps; };
    hooks.max_steps = o.steps;
    if (const std::string status = run_to_end(sim, hooks); status.rfind("failed: ", 0) == 0)
      throw RunFailure(c.file + ": " + status.substr(8));
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    if (record) {
      set_ccd_observer(nullptr);
      // Sorted: the same file for any number of threads.
      std::sort(recorded.begin(), recorded.end());
      std::string text;
      long ee = 0;
      for (const std::string& line : recorded) text += line + "\n", ee += line[0] == 'e';
      write_file_atomic(o.ccd_queries, text);
      if (!o.json)
        std::printf(
            "%ld edge–edge and %ld vertex–face exact CCD queries of %s's %ld steps written "
            "to %s (time them: tetcontact ccd %s --fcl --quiet)\n",
            ee, static_cast<long>(recorded.size()) - ee, m.c_str(), steps, o.ccd_queries.c_str(),
            o.ccd_queries.c_str());
      recorded.clear();
    }
    const double tets = static_cast<double>(sim.model().mesh.tets.size());
    const double bytes_per_tet = (resident_bytes() - resident_before) / std::max(1.0, tets);
    const auto& ct = sim.contact_totals();
    const double n = std::max(1L, steps);
    const double cand = ct.candidates / n, cont = ct.node_face / n;
    double bp = 0.0, contact = 0.0;  // broadphase; broadphase + narrowphase + response
    for (const auto& [name, sec] : sim.profile().stages) {
      if (name == "broadphase") bp = sec;
      if (name == "broadphase" || name == "narrowphase" || name == "response") contact += sec;
    }
    Json j = Json::object();
    j["method"] = m;
    j["primitives"] = nodes + faces;
    j["nodes"] = nodes;
    j["faces"] = faces;
    j["steps"] = steps;
    j["tets"] = tets;
    j["threads"] = parallel::threads();
    j["bytes_per_tet"] = bytes_per_tet;
    j["broadphase_runs"] = ct.rebuilds;
    j["candidates_per_step"] = cand;
    j["contacts_per_step"] = cont;
    j["pruning_ratio"] = all_pairs > 0 ? cand / all_pairs : 0.0;
    j["contacts_over_candidates"] = cand > 0 ? cont / cand : 0.0;
    // The correction passes run island by island on the threads: the largest island's share
    // of the points bounds their speed-up.
    j["islands_per_step"] = ct.islands / n;
    j["largest_island_share"] =
        ct.island_points > 0 ? double(ct.largest_island_points) / ct.island_points : 0.0;
    Json& sec = j["seconds_per_step"];
    sec["build"] = ct.broadphase_build / n;
    sec["query"] = ct.broadphase_query / n;
    sec["broadphase"] = bp / n;
    sec["step"] = wall / n;
    j["broadphase_share"] = wall > 0 ? bp / wall : 0.0;
    j["contact_share"] = wall > 0 ? contact / wall : 0.0;
    out.push_back(j);
    if (!o.json)
      std::printf(
          "%-12s %10.0f %11.1f %10.1f %10.3e %10.3f %9.3f %9.3f %9.3f %8.1f%% %8.1f%% %8.1f "
          "%7.1f%% %7.0f\n",
          m.c_str(), nodes + faces, cand, cont, all_pairs > 0 ? cand / all_pairs : 0.0,
          cand > 0 ? cont / cand : 0.0, 1e3 * ct.broadphase_build / n,
          1e3 * ct.broadphase_query / n, 1e3 * wall / n, wall > 0 ? 100 * bp / wall : 0.0,
          wall > 0 ? 100 * contact / wall : 0.0, ct.islands / n,
          ct.island_points > 0 ? 100.0 * ct.largest_island_points / ct.island_points : 0.0,
          bytes_per_tet);
  }
  if (o.json) std::cout << out.dump(2) << "\n";
  return 0;
}

int profile_frames(const ProfileOptions& o) {
  const TriangleSurface a = read_ply(o.frames[0]);
  const TriangleSurface b = read_ply(o.frames[1]);
  if (a.x.size() != b.x.size() || a.triangles != b.triangles)
    throw PlyError(o.frames[1] + ": not the same surface as " + o.frames[0] +
                   " (vertex count or triangles differ)");
  const auto edges = surface_edges(a);
  BroadphaseInput in;
  in.self_pairs = true;
  for (std::size_t v = 0; v < a.x.size(); ++v) {
    in.node_box.push_back(swept_box({&a.x[v], &b.x[v]}, o.margin));
    in.node_id.push_back(static_cast<Index>(v));
    in.node_body.push_back(0);
  }
  for (const auto& t : a.triangles) {
    in.face_box.push_back(swept_box(
        {&a.x[t[0]], &a.x[t[1]], &a.x[t[2]], &b.x[t[0]], &b.x[t[1]], &b.x[t[2]]}, o.margin));
    in.face_nodes.push_back(t);
    in.face_body.push_back(0);
  }
  for (const auto& e : edges) {
    in.edge_box.push_back(swept_box({&a.x[e[0]], &a.x[e[1]], &b.x[e[0]], &b.x[e[1]]}, o.margin));
    in.edge_nodes.push_back(e);
    in.edge_body.push_back(0);
  }
  const double pairs = static_cast<double>(a.x.size()) * a.triangles.size() +
                       0.5 * static_cast<double>(edges.size()) * edges.size();
  Json out = Json::array();
  const bool again = o.repeat > 1;
  if (!o.json) {
    std::printf("%zu vertices, %zu triangles, %zu edges, margin %g m\n%-12s %12s %12s %10s %10s",
                a.x.size(), a.triangles.size(), edges.size(), o.margin, "method", "ee_pairs",
                "vf_pairs", "build ms", "query ms");
    if (again) std::printf(" %14s %14s", "last build ms", "last query ms");
    std::printf("\n");
  }
  for (const std::string& m : methods_for(o.method, pairs)) {
    auto bp = make_broadphase(m);
    const Candidates c = bp->find(in);
    const double build = bp->build_seconds, query = bp->query_seconds;
    for (int k = 1; k < o.repeat; ++k)
      if (const Candidates again_c = bp->find(in);  // the lists must not change between calls
          again_c.edge_edge != c.edge_edge || again_c.node_face != c.node_face)
        throw std::runtime_error(m + ": call " + std::to_string(k + 1) +
                                 " listed other pairs than the first");
    Json j = Json::object();
    j["method"] = m;
    j["primitives"] = in.node_box.size() + in.face_box.size() + in.edge_box.size();
    j["ee_pairs"] = c.edge_edge.size();
    j["vf_pairs"] = c.node_face.size();
    j["build_seconds"] = build;
    j["query_seconds"] = query;
    if (again) {
      j["last_build_seconds"] = bp->build_seconds;
      j["last_query_seconds"] = bp->query_seconds;
    }
    out.push_back(j);
    if (!o.json) {
      std::printf("%-12s %12zu %12zu %10.2f %10.2f", m.c_str(), c.edge_edge.size(),
                  c.node_face.size(), 1e3 * build, 1e3 * query);
      if (again) std::printf(" %14.2f %14.2f", 1e3 * bp->build_seconds, 1e3 * bp->query_seconds);
      std::printf("\n");
    }
  }
  if (o.json) std::cout << out.dump(2) << "\n";
  return 0;
}

}  // namespace

int profile_command(const ProfileOptions& o) {
  try {
    return o.frames.empty() ? profile_case(o) : profile_frames(o);
  } catch (const CaseError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
  } catch (const SetupError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
  } catch (const PlyError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
  } catch (const std::invalid_argument& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
  }
  return 2;
}

}  // namespace tc
