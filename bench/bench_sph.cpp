// The SPH faces' integrals: ns per particle–face call of sph::face_kernel, in each of its lane
// copies (0 one Gauss point at a time, 1 SSE2, 2 AVX2, 3 AVX-512). Not a test: `make bench`
// prints the figures; docs/guide/benchmarks.md quotes them with the machine.
#include <benchmark/benchmark.h>

#include <array>
#include <random>
#include <vector>

#include "tetcontact/sph/boundary.hpp"

using namespace tc;

namespace {

// Faces of a body's surface as the SPH stage meets them: triangles of edge about h (a cell of
// the size the particle was made from), their centroids within the kernel's reach 2h of the
// particle, which sits at the origin.
struct FaceSet {
  std::vector<sph::FaceShape> shapes;
};

FaceSet near_faces(int count, double h) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  FaceSet set;
  while (static_cast<int>(set.shapes.size()) < count) {
    const Vec3 centre(u(rng), u(rng), u(rng));
    if (centre.norm() > 1.0) continue;
    const Vec3 at = 2.0 * h * centre;
    const Vec3 a = at + 0.6 * h * Vec3(u(rng), u(rng), u(rng));
    const Vec3 b = at + 0.6 * h * Vec3(u(rng), u(rng), u(rng));
    const Vec3 c = at + 0.6 * h * Vec3(u(rng), u(rng), u(rng));
    set.shapes.push_back(sph::face_shape(a, b, c));
  }
  return set;
}

void BM_FaceKernel(benchmark::State& state) {
  const auto lanes = static_cast<Lanes>(state.range(0));
  if (static_cast<int>(lanes) > static_cast<int>(widest_lanes())) {
    state.SkipWithError("lanes wider than this processor runs");
    return;
  }
  const Lanes was = sph::set_face_lanes(lanes);
  const double h = 1.0e-4;
  const FaceSet set = near_faces(4096, h);
  int met = 0;
  for (auto _ : state) {
    double sum = 0.0;
    for (const sph::FaceShape& f : set.shapes) sum += sph::face_kernel(Vec3::Zero(), f, h).phi;
    benchmark::DoNotOptimize(sum);
    met = sum > 0.0;
  }
  sph::set_face_lanes(was);
  state.counters["met"] = met;
  state.counters["ns_per_face"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * static_cast<double>(set.shapes.size()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

BENCHMARK(BM_FaceKernel)->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);
