// `tetcontact partition`: the decomposition a distributed run would use, reported
// before any run: per rank its tets, boundary faces, nodes, shared and ghost nodes, the faces
// cut and the imbalance of the element and contact work.
#pragma once

#include <string>
#include <vector>

#include "tetcontact/io/json.hpp"
#include "tetcontact/mesh/partition.hpp"

namespace tc {

struct PartitionOptions {
  std::string case_path;
  int ranks = 2;
  bool json = false;
  bool tets_only = false;  // balance the tets alone (no contact constraint)
  std::vector<std::string> overrides;
};

/// The report of a decomposition: ranks, faces cut, the imbalances, and per rank (`pieces`) its
/// tets, boundary faces, nodes, shared and ghost nodes. `partition --json` prints it; a
/// distributed run's summary holds it as `parallel.partition`.
Json partition_json(const Partition& p);

/// Exit codes: 0, 2 bad input (the case, or more ranks than tets).
int partition_command(const PartitionOptions& options);

}  // namespace tc
