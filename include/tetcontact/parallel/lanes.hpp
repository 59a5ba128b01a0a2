// SIMD lanes: the instruction sets a stage's lane copies are compiled for.
//
// A stage that runs in lanes (the element kernel's cells, the SPH faces' Gauss points, the exact
// sums' parts) writes its body once, as plain loops over arrays, and inlines it into one function
// per instruction set (GCC's `target` attribute: one binary for every x86-64, no -march flag).
// Each copy gives the scalar path's doubles (the kernel's and the faces' files are compiled with
// -ffp-contract=off; the exact sums are exact in any copy); the widest the processor runs is
// chosen when the program starts, and a test runs every copy against the scalar path.
#pragma once

// The targets of the AVX2 and AVX-512 copies (plain functions where GCC's x86 targets do not
// exist: widest_lanes() never chooses them there).
#if defined(__x86_64__) && defined(__GNUC__)
#define TC_TARGET_AVX2 __attribute__((target("avx2")))
#define TC_TARGET_AVX512 __attribute__((target("avx512f")))
#else
#define TC_TARGET_AVX2
#define TC_TARGET_AVX512
#endif

namespace tc {

/// One item at a time (`scalar`, the reference), or lanes compiled for SSE2 (every x86-64),
/// AVX2 (four doubles a register) or AVX-512 (eight).
enum class Lanes { scalar, sse2, avx2, avx512 };

/// The widest lanes this processor runs.
Lanes widest_lanes();

/// `lanes`, or std::invalid_argument naming the stage where they are wider than widest_lanes().
Lanes runnable_lanes(Lanes lanes, const char* stage);

/// Of a stage's four copies, the one for `lanes`.
template <class Copy>
Copy copy_for(Lanes lanes, Copy scalar, Copy sse2, Copy avx2, Copy avx512) {
  switch (lanes) {
    case Lanes::scalar:
      return scalar;
    case Lanes::avx2:
      return avx2;
    case Lanes::avx512:
      return avx512;
    default:
      return sse2;
  }
}

}  // namespace tc
