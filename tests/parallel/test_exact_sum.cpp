// The exact sum against GMP's rationals (every double is one): the value is the exact sum
// rounded to the nearest double, ties to even; and it is the same bits for any order of the
// terms and any split into merged partial sums (what a distributed run does).
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "tetcontact/parallel/exact_sum.hpp"

using tc::ExactSum;

namespace {

mpq_class exact(double x) {
  mpq_class q;
  mpq_set_d(q.get_mpq_t(), x);
  return q;
}

// r is the exact value rounded to nearest, ties to even.
::testing::AssertionResult rounds_correctly(const mpq_class& sum, double r) {
  if (!std::isfinite(r)) return ::testing::AssertionFailure() << "not finite: " << r;
  const mpq_class d = abs(sum - exact(r));
  for (const double n : {std::nextafter(r, -INFINITY), std::nextafter(r, INFINITY)}) {
    if (!std::isfinite(n)) continue;
    const mpq_class dn = abs(sum - exact(n));
    if (dn < d) return ::testing::AssertionFailure() << r << " is not the nearest (" << n << ")";
    if (dn == d && (std::bit_cast<std::uint64_t>(r) & 1))
      return ::testing::AssertionFailure() << r << ": a tie not rounded to even (" << n << ")";
  }
  return ::testing::AssertionSuccess();
}

double term(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-1074, 1000), kind(0, 9);
  switch (kind(rng)) {
    case 0:  // a subnormal
      return std::ldexp(unit(rng), -1060);
    case 1:  // a huge value
      return std::ldexp(unit(rng), 1000);
    case 2:
    case 3:  // near 1 (most sums: cancellations between them)
      return 1.0 + std::ldexp(unit(rng), -40);
    default:
      return std::ldexp(unit(rng), exponent(rng) / 8);
  }
}

}  // namespace

TEST(ExactSum, RoundsTheExactSumToNearestEven) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 1 + trial % 60;
    std::vector<double> xs;
    for (int i = 0; i < n; ++i) xs.push_back(term(rng));
    if (trial % 3 == 0)  // cancellation down to the last terms
      for (int i = 0; i < n; ++i) xs.push_back(-xs[i] * (i % 2 ? 1.0 : 1.0 + 0x1p-52));
    ExactSum s;
    mpq_class sum = 0;
    for (const double x : xs) s.add(x), sum += exact(x);
    EXPECT_TRUE(rounds_correctly(sum, s.value())) << "trial " << trial;
  }
}

TEST(ExactSum, HandlesTiesZerosSubnormalsAndNonFiniteValues) {
  ExactSum zero;
  EXPECT_EQ(std::bit_cast<std::uint64_t>(zero.value()), 0u);
  // 1 + 2^-53 is a tie between 1 and 1 + 2^-52: to even, 1; with 2^-200 more, above the tie.
  ExactSum tie;
  tie.add(1.0);
  tie.add(0x1p-53);
  EXPECT_EQ(tie.value(), 1.0);
  tie.add(0x1p-200);
  EXPECT_EQ(tie.value(), 1.0 + 0x1p-52);
  // (1 + 2^-52) + 2^-53: a tie to the even 1 + 2^-51.
  ExactSum odd;
  odd.add(1.0 + 0x1p-52);
  odd.add(0x1p-53);
  EXPECT_EQ(odd.value(), 1.0 + 0x1p-51);
  // Naive summation loses the small term; the exact sum keeps it.
  ExactSum big;
  for (const double x : {1e100, 1.0, -1e100}) big.add(x);
  EXPECT_EQ(big.value(), 1.0);
  ExactSum sub;
  sub.add(std::numeric_limits<double>::denorm_min());
  sub.add(std::numeric_limits<double>::denorm_min());
  sub.add(-0x1p-1073 * 3);
  EXPECT_EQ(sub.value(), -0x1p-1072);  // 2 · 2^-1074 − 3 · 2^-1073
  ExactSum inf;
  inf.add(1.0);
  inf.add(INFINITY);
  EXPECT_EQ(inf.value(), INFINITY);
  inf.add(-INFINITY);
  EXPECT_TRUE(std::isnan(inf.value()));
}

TEST(ExactSum, SameBitsForAnyOrderAndAnySplitIntoMergedPartials) {
  std::mt19937_64 rng(11);
  std::vector<double> xs;
  for (int i = 0; i < 5000; ++i) xs.push_back(term(rng) * (i % 7 == 0 ? 1e-30 : 1.0));
  ExactSum one;
  double naive = 0.0;
  for (const double x : xs) one.add(x), naive += x;
  for (int trial = 0; trial < 20; ++trial) {
    std::shuffle(xs.begin(), xs.end(), rng);
    const int parts = 1 + trial % 5;
    std::vector<ExactSum> partial(parts);
    for (std::size_t i = 0; i < xs.size(); ++i) partial[(i * 7919) % parts].add(xs[i]);
    ExactSum merged;
    for (const ExactSum& p : partial) merged.merge(p);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(merged.value()),
              std::bit_cast<std::uint64_t>(one.value()))
        << "trial " << trial;
  }
  // The order mattered to the naive sum of the same terms (the check can fail).
  double reordered = 0.0;
  for (const double x : xs) reordered += x;
  EXPECT_NE(std::bit_cast<std::uint64_t>(naive), std::bit_cast<std::uint64_t>(reordered));
}

// add_all splits each chunk's values into three parts summed in doubles without error; what the
// parts leave goes one by one. Its sum must be the one-by-one sum exactly: the two cancel to 0,
// in every copy of its lanes the processor runs.
TEST(ExactSum, AddAllIsTheOneByOneSumExactly) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto energies = [&](std::size_t n) {  // a run's cells: some decades, some zeros
    std::vector<double> xs(n);
    for (double& x : xs) x = unit(rng) < 0.1 ? 0.0 : std::ldexp(unit(rng), -(int)(unit(rng) * 40));
    return xs;
  };
  const auto wide = [&](std::size_t n) {
    std::vector<double> xs(n);
    for (double& x : xs) x = term(rng);
    return xs;
  };
  const auto near_one = [&](std::size_t n) {  // cancellation, the maximum a power of two
    std::vector<double> xs(n);
    for (std::size_t i = 0; i < n; ++i)
      xs[i] = (i % 2 ? -1.0 : 1.0) * (i % 5 == 0 ? 1.0 : 1.0 - std::ldexp(unit(rng), -30));
    return xs;
  };
  const auto scaled = [&](std::vector<double> xs, double f) {
    for (double& x : xs) x *= f;
    return xs;
  };
  const auto topped = [](std::vector<double> xs) {  // each chunk's largest 0.75
    for (std::size_t i = 0; i < xs.size(); i += 1024) xs[i] = 0.75;
    return xs;
  };
  // Each set with the path its chunks must take: by their parts, with values left below them,
  // or one by one.
  enum class Path { parts, leftover, one_by_one };
  struct Set {
    std::vector<double> xs;
    Path path;
  };
  std::vector<Set> sets;
  for (const std::size_t n : {1u, 7u, 8u, 9u, 1023u, 1024u, 1025u, 5000u}) {
    sets.push_back({energies(n), Path::parts});
    sets.push_back({near_one(n), Path::parts});
    sets.push_back({scaled(energies(n), 0x1p-880), Path::parts});        // the parts near underflow
    sets.push_back({scaled(energies(n), 0x1p-1000), Path::one_by_one});  // below the parts
    sets.push_back({scaled(topped(energies(n)), 0x1p+1005), Path::one_by_one});  // above them
    if (n >= 1023) sets.push_back({wide(n), Path::leftover});  // 2^1000 beside subnormals
    if (n >= 8) {
      std::vector<double> low = scaled(energies(n), 0x1p-880);  // subnormals and −0 among them
      low[n / 2] = -0.0;
      low[n / 3] = std::numeric_limits<double>::denorm_min() * 3.0;
      low[n / 4] = -0x1p-1030;
      sets.push_back({low, Path::leftover});
    }
  }
  std::size_t naive_differs = 0;
  const tc::Lanes widest = tc::widest_lanes();
  EXPECT_NE(widest, tc::Lanes::scalar);
  const auto lanes_run = [&] {
    std::vector<tc::Lanes> run;
    for (const tc::Lanes l : {tc::Lanes::sse2, tc::Lanes::avx2, tc::Lanes::avx512})
      if (l <= widest) run.push_back(l);
    return run;
  }();
  for (std::size_t k = 0; k < sets.size(); ++k) {
    const std::vector<double>& xs = sets[k].xs;
    mpq_class sum = 0;
    ExactSum one;
    for (const double x : xs) one.add(x), sum += exact(x);
    for (const tc::Lanes lanes : lanes_run) {
      ExactSum all, diff;
      const ExactSum::Chunks chunks = all.add_all(xs.data(), xs.size(), lanes);
      diff.add_all(xs.data(), xs.size(), lanes);
      for (const double x : xs) diff.add(-x);
      const std::string at =
          "set " + std::to_string(k) + ", lanes " + std::to_string(static_cast<int>(lanes));
      EXPECT_EQ(std::bit_cast<std::uint64_t>(diff.value()), 0u) << at;
      EXPECT_EQ(std::bit_cast<std::uint64_t>(all.value()),
                std::bit_cast<std::uint64_t>(one.value()))
          << at;
      // The path the set was made for was taken.
      const std::size_t count = (xs.size() + 1023) / 1024;
      switch (sets[k].path) {
        case Path::parts:  // every chunk but one of zeros only
          EXPECT_GE(chunks.split + 1, count) << at;
          EXPECT_GT(chunks.split, 0u) << at;
          EXPECT_EQ(chunks.leftover, 0u) << at;
          break;
        case Path::leftover:
          EXPECT_GT(chunks.leftover, 0u) << at;
          break;
        case Path::one_by_one:
          EXPECT_EQ(chunks.split, 0u) << at;
          break;
      }
    }
    ExactSum all;
    all.add_all(xs.data(), xs.size());
    EXPECT_TRUE(rounds_correctly(sum, all.value())) << "set " << k;
    // Naive summation differs from the exact sum on many of these: the check can fail.
    double naive = 0.0;
    for (const double x : xs) naive += x;
    naive_differs += naive != all.value();
  }
  EXPECT_GT(naive_differs, sets.size() / 4);
  // Lanes wider than the processor runs are refused.
  if (widest != tc::Lanes::avx512) {
    ExactSum wider;
    EXPECT_THROW(wider.add_all(sets[0].xs.data(), sets[0].xs.size(), tc::Lanes::avx512),
                 std::invalid_argument);
  }
  // Non-finite values: their IEEE sum, as add gives, in every copy.
  for (const tc::Lanes lanes : lanes_run) {
    std::vector<double> xs = energies(100);
    xs[40] = INFINITY;
    ExactSum inf;
    inf.add_all(xs.data(), xs.size(), lanes);
    EXPECT_EQ(inf.value(), INFINITY);
    xs[60] = std::numeric_limits<double>::quiet_NaN();
    ExactSum nan;
    nan.add_all(xs.data(), xs.size(), lanes);
    EXPECT_TRUE(std::isnan(nan.value()));
  }
}
