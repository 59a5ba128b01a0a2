// `tetcontact stress`: the exact CCD against degenerate query families whose answers are known
// by construction (not by another CCD), at coordinates from 1e-9 to 1e9.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "tetcontact/diagnostics/expect.hpp"

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

struct StressQuery {
  bool edge_edge = false;  // else vertex–face
  std::array<Vec3, 8> q;   // the ccd file's order: four points at t = 0, then at t = 1
  bool truth = false;      // the constructed answer
};

struct StressFamily {
  std::string name;
  std::string description;
  std::vector<StressQuery> queries;
};

/// The families, `count` queries each, from `seed` (deterministic for a given build). Every
/// query is placed by an exact transformation (axis permutation and signs, an integer
/// offset, a power-of-two scale 2^-30 … 2^30, time reversal, primitive and endpoint order),
/// which leaves its answer unchanged.
std::vector<StressFamily> stress_families(std::uint64_t seed, int count);

/// A micro-scene: a small case (data/cases/micro/) that puts bodies in a degenerate contact
/// (coincident faces, an edge lying in a face, a vertex on an edge, a single touching point)
/// and runs the solver through it.
struct SceneResult {
  std::string name;  // the case file's stem
  long steps = 0;
  std::string status = "ok";    // or what stopped it (non-finite values, inverted element, …)
  double momentum_error = 0.0;  // |ΔP − external impulse| / momentum scale
  double balance_error = 0.0;   // the energy balance's largest relative error over the run
  Penetration penetration;      // maxima of the diagnostics over the steps
  std::vector<ExpectResult> expect;  // the scene's `expect:` bounds, against those maxima
  /// Status ok, momentum conserved to 1e-12 and every bound of the scene's `expect:` held.
  bool pass = false;
  long impact_zones = 0;  // made by the step verification (contact.verify)
};

/// Runs every `*.yaml` in `dir` (sorted by name), with `overrides` (--set) applied to each,
/// measuring penetration after every step. Throws std::runtime_error when `dir` holds no case.
std::vector<SceneResult> run_micro_scenes(const std::string& dir,
                                          const std::vector<std::string>& overrides = {});

/// Generated whole-solver scenes: a 1 cm box of 2 × 2 × 2 cells and a 6 mm box or
/// ball, `count` of them from `seed`, in turn (a) both turned at random, the projectile on a
/// random side 0 to 0.5 mm beyond the bounding spheres, with a sideways component and spin;
/// (b) touching face on face at t = 0 (z = 0.005 exactly), the projectile turned about z and
/// pressing down while sliding; (c) touching and sliding, barely pressing. Speeds 0.1 to
/// 7 km/s (log-uniform); edge–edge contact and the step verification on. Case-file texts.
std::vector<std::string> solver_scene_cases(std::uint64_t seed, int count);
/// Runs them (with `overrides`), measuring the penetration after every step.
std::vector<SceneResult> run_solver_scenes(std::uint64_t seed, int count,
                                           const std::vector<std::string>& overrides = {});

/// Where the shipped micro-scenes are (data/cases/micro).
std::string default_scenes_dir();

struct StressOptions {
  std::uint64_t seed = 1;
  int count = 1000;
  bool json = false;
  bool scenes = true;
  std::string scenes_dir;              // empty: default_scenes_dir()
  std::vector<std::string> overrides;  // --set, applied to every micro-scene
  int solver_scenes = 0;               // generated whole-solver scenes to run (0: none)
};

/// Prints a table (or JSON) per family and per micro-scene; exit code 0 when no query
/// disagrees and every scene passes, 1 otherwise.
int stress_command(const StressOptions& options);

}  // namespace tc
