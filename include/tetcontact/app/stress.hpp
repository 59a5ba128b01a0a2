// `tetcontact stress`: the exact CCD against degenerate query families whose answers are known
// by construction (not by another CCD), at coordinates from 1e-9 to 1e9.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

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

struct StressOptions {
  std::uint64_t seed = 1;
  int count = 1000;
  bool json = false;
};

/// Prints a table (or JSON) per family; exit code 0 when no query disagrees, 1 otherwise.
int stress_command(const StressOptions& options);

}  // namespace tc
