// The balance's exact sums over tets: ns per tet of the three sums a step takes (internal
// energy, plastic and viscous work) of ExactSum, one value at a time (lanes 0) or by add_all in
// its lane copies (1 SSE2, 2 AVX2, 3 AVX-512), on values spread as a run's cells are. Not a
// test: `make bench` prints the figures; docs/guide/benchmarks.md quotes them with the machine.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "tetcontact/parallel/exact_sum.hpp"

using namespace tc;

namespace {

// A run's cells: energies over some ten decades, the plastic work zero in most cells.
std::array<std::vector<double>, 3> cell_fields(std::size_t n) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::array<std::vector<double>, 3> f;
  for (auto& v : f) v.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    f[0][i] = 1e-3 * std::pow(10.0, -10.0 * u(rng));
    f[1][i] = u(rng) < 0.8 ? 0.0 : 1e-3 * u(rng);
    f[2][i] = 1e-6 * std::pow(10.0, -6.0 * u(rng));
  }
  return f;
}

void BM_ExactSums(benchmark::State& state) {
  const auto lanes = static_cast<Lanes>(state.range(0));
  if (lanes > widest_lanes()) {
    state.SkipWithError("lanes wider than this processor runs");
    return;
  }
  constexpr std::size_t n = 100000, block = 1024;
  const auto f = cell_fields(n);
  for (auto _ : state) {
    std::array<ExactSum, 3> s;
    for (int k = 0; k < 3; ++k)
      for (std::size_t b = 0; b < n; b += block)
        s[k].add_all(&f[k][b], std::min(block, n - b), lanes);
    benchmark::DoNotOptimize(s[0].value() + s[1].value() + s[2].value());
  }
  state.counters["ns_per_tet"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(n),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

BENCHMARK(BM_ExactSums)->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);
