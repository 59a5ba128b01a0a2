// `tetcontact partition`: the decomposition a distributed run would use (issue 16), reported
// before any run: per rank its tets, boundary faces, nodes, shared and ghost nodes, the faces
// cut and the imbalance of the element and contact work.
#pragma once

#include <string>
#include <vector>

namespace tc {

struct PartitionOptions {
  std::string case_path;
  int ranks = 2;
  bool json = false;
  bool tets_only = false;  // balance the tets alone (no contact constraint)
  std::vector<std::string> overrides;
};

/// Exit codes: 0, 2 bad input (the case, or more ranks than tets).
int partition_command(const PartitionOptions& options);

}  // namespace tc
