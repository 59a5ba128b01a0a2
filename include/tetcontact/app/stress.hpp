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
};

/// Runs every `*.yaml` in `dir` (sorted by name), with `overrides` (--set) applied to each,
/// measuring penetration after every step. Throws std::runtime_error when `dir` holds no case.
std::vector<SceneResult> run_micro_scenes(const std::string& dir,
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
};

/// Prints a table (or JSON) per family and per micro-scene; exit code 0 when no query
/// disagrees and every scene passes, 1 otherwise.
int stress_command(const StressOptions& options);

}  // namespace tc
