// `tetcontact profile`: broadphase pruning and cost, on a case or on two frames of a surface.
#pragma once

#include <string>
#include <vector>

namespace tc {

struct ProfileOptions {
  std::string case_path;            // case mode
  std::vector<std::string> frames;  // frames mode: A.ply B.ply
  std::string method = "all";
  double margin = 0.0;  // frames mode
  /// frames mode: calls per method; the last one's times are reported beside the first's (a run
  /// calls its broadphase every step, keeping what the method keeps between calls).
  int repeat = 1;
  long steps = 100;  // case mode: steps per method (the whole case when shorter)
  bool json = false;
  /// case mode: write the exact CCD queries the first method's steps asked (contact detection
  /// and verification) to this file, in `ccd`'s format (time them with `ccd FILE --fcl`).
  std::string ccd_queries;
  std::vector<std::string> overrides;
};

/// Exit codes: 0, 2 bad input.
int profile_command(const ProfileOptions& options);

}  // namespace tc
