#include "tetcontact/parallel/lanes.hpp"

#include <stdexcept>
#include <string>

namespace tc {

Lanes widest_lanes() {
#if defined(__x86_64__) && defined(__GNUC__)
  if (__builtin_cpu_supports("avx512f")) return Lanes::avx512;
  if (__builtin_cpu_supports("avx2")) return Lanes::avx2;
#endif
  return Lanes::sse2;
}

Lanes runnable_lanes(Lanes lanes, const char* stage) {
  if (static_cast<int>(lanes) > static_cast<int>(widest_lanes()))
    throw std::invalid_argument(std::string(stage) + " lanes wider than this processor runs");
  return lanes;
}

}  // namespace tc
