// `tetcontact ccd FILE`: exact continuous collision queries from a file (../shared/ccd format).
#pragma once

#include <string>

namespace tc {

struct CcdOptions {
  std::string file;
  bool json = false;
  bool quiet = false;   // no per-query lines
  bool toi = false;     // earliest time of impact after each `1`
  bool fcl = false;     // FCL 0.7's cubic CCD on the same queries, for comparison
  std::string confirm;  // "cgal": every answer checked by the CGAL oracle (cgal_ccd.hpp)
};

/// Exit codes: 0, 2 bad input.
int ccd_command(const CcdOptions& options);

}  // namespace tc
