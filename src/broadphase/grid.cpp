// The contact-boundary notes' spatial index: a uniform grid of cubes (i, j, k), the occupied ones
// numbered through a hash table. Each box is entered in every cube it overlaps; a cube's
// entries lie together, in primitive order, as single-precision boxes in a structure of arrays.
// The build runs on the threads a block of boxes each (each block's cubes in a table of its
// own); only joining the blocks' cubes, one lookup a cube, is serial.
//
// A pair of overlapping boxes is counted in one cube only: the cube that holds the lower corner
// of their intersection. Per axis that cube's index is max(⌊lo_a/h⌋, ⌊lo_b/h⌋) (the floor is
// monotone), and since both boxes reach the cube it is the first cube along that axis of a or of
// b. So an entry carries three bits (this is my first cube along x, y, z), and a pair is
// counted where the two entries' bits together cover all three axes.
//
// Queries run per primitive, in primitive order and in blocks on the threads: a node tests the
// face entries of its cubes, an edge the entries after its own in each of its cubes (the larger
// indices). Each cube gives its partners already sorted; the runs of a primitive's few cubes are
// merged. So the candidates come out sorted by construction, with no global sort.
//
// Single precision, exactly: the float boxes are rounded outward (lo down, hi up), so their
// test passes every pair the double test passes; the few that pass on rounding alone are
// dropped by the double test, which runs on the float test's hits only. The lists equal the
// brute-force test of the double boxes.
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "tetcontact/broadphase/broadphase.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The float next to a finite f, one step toward -inf or +inf (std::nextafter without the call).
float step_down(float f) {
  if (f == 0.0f) return -std::numeric_limits<float>::denorm_min();
  const auto bits = std::bit_cast<std::uint32_t>(f);
  return std::bit_cast<float>(f > 0.0f ? bits - 1 : bits + 1);
}
float step_up(float f) {
  return -step_down(-f);
}

// v rounded to a float below (at or under v) and above (at or over v). Finite v only.
float round_down(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? step_down(f) : f;
}
float round_up(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) < v ? step_up(f) : f;
}

// Cube indices of a box: lo[a]..hi[a] along each axis a.
struct CubeRange {
  std::int64_t lo[3], hi[3];
  std::int64_t count() const {
    return (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
  }
};

// Transparent huge pages for a buffer about to be written for the first time: its whole 2 MiB
// pages (Linux, where the system's policy is "madvise"; elsewhere nothing). The pair lists run to
// a hundred megabytes at scale, and written in 4 KiB pages their page faults took from 15 % to
// over half of the broadphase's time, as the machine's faults were cheap or dear
// (docs/guide/benchmarks.md).
void advise_huge_pages(const void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21;
  if (bytes < 4 * kHuge) return;
  const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(p) + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(kHuge - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

// The allocator of the grid's arrays and the blocks' pair lists: huge pages for the large ones.
template <class T>
struct HugePages {
  using value_type = T;
  HugePages() = default;
  template <class U>
  HugePages(const HugePages<U>&) {}  // NOLINT: rebinding converts
  T* allocate(std::size_t n) {
    T* p = std::allocator<T>{}.allocate(n);
    advise_huge_pages(p, n * sizeof(T));
    return p;
  }
  void deallocate(T* p, std::size_t n) { std::allocator<T>{}.deallocate(p, n); }
  friend bool operator==(const HugePages&, const HugePages&) { return true; }
  friend bool operator!=(const HugePages&, const HugePages&) { return false; }
};
template <class T>
using HugeVector = std::vector<T, HugePages<T>>;
using PairBlock = HugeVector<std::pair<Index, Index>>;

// Entries of padding after the last, for the lanes.
constexpr std::size_t kPad = 8;

// Occupied cubes' numbers by key: open addressing (kEmpty where free).
struct CubeTable {
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  HugeVector<std::uint64_t> keys;
  HugeVector<Index> ids;
  std::uint64_t mask = 0;

  HugeVector<std::uint64_t> spare_keys;  // grow's scratch
  HugeVector<Index> spare_ids;

  /// Empty, with room for n cubes at half load or less (or the room it had, if more).
  void reset(std::size_t n) {
    std::size_t size = std::max<std::size_t>(64, keys.size());
    while (size < 2 * n) size *= 2;
    mask = size - 1;
    keys.assign(size, kEmpty);
    ids.resize(size);
  }
  /// Twice the room, every cube kept with its number.
  void grow() {
    spare_keys.swap(keys);
    spare_ids.swap(ids);
    const std::size_t size = 2 * spare_keys.size();
    mask = size - 1;
    keys.assign(size, kEmpty);
    ids.resize(size);
    for (std::size_t s = 0; s < spare_keys.size(); ++s)
      if (spare_keys[s] != kEmpty) insert(spare_keys[s], spare_ids[s]);
  }
  static std::uint64_t slot_of(std::uint64_t key) {  // splitmix64's finaliser
    key ^= key >> 30;
    key *= 0xbf58476d1ce4e5b9ULL;
    key ^= key >> 27;
    key *= 0x94d049bb133111ebULL;
    key ^= key >> 31;
    return key;
  }
  /// The cube's number, or -1 when it is not in the table.
  Index find(std::uint64_t k) const {
    for (std::uint64_t s = slot_of(k) & mask;; s = (s + 1) & mask) {
      if (keys[s] == k) return ids[s];
      if (keys[s] == kEmpty) return -1;
    }
  }
  /// The cube's number; `next` if it was not in the table (it is now).
  Index insert(std::uint64_t k, Index next) {
    for (std::uint64_t s = slot_of(k) & mask;; s = (s + 1) & mask) {
      if (keys[s] == k) return ids[s];
      if (keys[s] == kEmpty) {
        keys[s] = k;
        ids[s] = next;
        return next;
      }
    }
  }
};

// The cubes one block of boxes enters, numbered in order of first entry within the block: each
// one's key, its entries from the block, and (after the blocks are joined) its number among all
// the cubes and the entries of earlier blocks before the block's own in it.
struct BlockCubes {
  CubeTable table;
  HugeVector<std::uint64_t> key;
  HugeVector<Index> count, global, before;
};

// The cubes of one set of boxes (the faces, or the edges).
struct Cubes {
  double h = 1.0;
  std::int64_t origin[3] = {0, 0, 0}, span[3] = {1, 1, 1};
  CubeTable table;  // the occupied cubes, numbered in order of first entry
  // Entries grouped by cube (cube c: start[c] ≤ e < start[c + 1]), in primitive order within it.
  HugeVector<Index> start;
  HugeVector<float> lox, loy, loz, hix, hiy, hiz;
  HugeVector<std::int32_t> first;  // bit 0, 1, 2: this cube is the box's first along x, y, z
  HugeVector<Index> item;
  // Each primitive's entries, in the order its cubes were visited: entry k lies in cube
  // entry_cube[k] at start[entry_cube[k]] + rank[k].
  HugeVector<Index> entry_begin, entry_cube, rank;
  // Scratch of the build, kept with the rest between calls (no allocation once warm).
  HugeVector<CubeRange> ranges;
  HugeVector<Index> next;
  std::vector<BlockCubes> blocks;  // per block of boxes (enter)

  // Clamped far beyond any occupied cube, so that a far node's box converts safely.
  std::int64_t cube_of(double v) const {
    return static_cast<std::int64_t>(std::clamp(std::floor(v / h), -4.0e18, 4.0e18));
  }
  CubeRange range(const Box& b) const {
    CubeRange r;
    for (int a = 0; a < 3; ++a) {
      r.lo[a] = cube_of(b.lo[a]);
      r.hi[a] = cube_of(b.hi[a]);
    }
    return r;
  }
  std::uint64_t key(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return (static_cast<std::uint64_t>(i - origin[0]) * static_cast<std::uint64_t>(span[1]) +
            static_cast<std::uint64_t>(j - origin[1])) *
               static_cast<std::uint64_t>(span[2]) +
           static_cast<std::uint64_t>(k - origin[2]);
  }
  /// The cube's number, or -1 when no box entered it.
  Index find(std::uint64_t k) const { return table.find(k); }
};

// The cube size asked for, or 1.5 times the mean box size (measured best on the scale frames of
// benchmarks.md: 1 and 2 were slower, smaller cubes making more entries, larger more tests),
// doubled while cube indices would leave a 64-bit key.
double cube_size(const std::vector<Box>& boxes, double asked) {
  double h = asked;
  if (!(h > 0.0)) {
    double sum = 0.0;
    for (const Box& b : boxes) sum += (b.hi - b.lo).maxCoeff();
    h = boxes.empty() ? 1.0 : 1.5 * sum / static_cast<double>(boxes.size());
    if (!(h > 0.0) || !std::isfinite(h)) h = 1.0;
  }
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Box& b : boxes) {
    if (!b.lo.allFinite() || !b.hi.allFinite())
      throw std::invalid_argument("broadphase: a box with a non-finite corner");
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  if (boxes.empty()) return h;
  for (;;) {
    double cubes = 1.0, reach = 0.0;
    for (int a = 0; a < 3; ++a) {
      reach = std::max(reach, std::max(std::abs(lo[a]), std::abs(hi[a])) / h);
      cubes *= std::floor(hi[a] / h) - std::floor(lo[a] / h) + 1.0;
    }
    if (reach < 1.0e15 && cubes < 4.0e18) return h;
    h *= 2.0;
  }
}

// Boxes entered in cubes of size h, or of 2h, 4h, ... while they would make more than 64 entries
// a box on average (a few boxes far larger than the rest).
void enter(Cubes& g, const std::vector<Box>& boxes, double h) {
  g.h = h;
  const std::size_t n = boxes.size();
  g.ranges.resize(n);
  // On the threads: each box's cubes, and their count.
  const double limit = 64.0 * static_cast<double>(n) + 1.0e6;
  const double counted = parallel::sum_blocks<double>(
      n,
      [&](std::size_t begin, std::size_t end) {
        double c = 0.0;
        for (std::size_t i = begin; i < end; ++i) {
          g.ranges[i] = g.range(boxes[i]);
          c += static_cast<double>(g.ranges[i].count());  // whole numbers: exact
        }
        return c;
      },
      parallel::k_light_block);
  if (counted > limit) return enter(g, boxes, 2.0 * h);
  const std::size_t entries = static_cast<std::size_t>(counted);
  for (int a = 0; a < 3; ++a) {
    g.origin[a] = 0;
    g.span[a] = 1;
  }
  if (n > 0) {
    std::int64_t top[3];
    for (int a = 0; a < 3; ++a) {
      g.origin[a] = g.ranges[0].lo[a];
      top[a] = g.ranges[0].hi[a];
    }
    for (const CubeRange& r : g.ranges)
      for (int a = 0; a < 3; ++a) {
        g.origin[a] = std::min(g.origin[a], r.lo[a]);
        top[a] = std::max(top[a], r.hi[a]);
      }
    for (int a = 0; a < 3; ++a) g.span[a] = top[a] - g.origin[a] + 1;
  }
  // Each box's entries: their place in the box order.
  g.entry_begin.resize(n + 1);
  g.entry_begin[0] = 0;
  for (std::size_t i = 0; i < n; ++i)
    g.entry_begin[i + 1] = g.entry_begin[i] + static_cast<Index>(g.ranges[i].count());
  g.entry_cube.resize(entries);
  g.rank.resize(entries);
  // On the threads, a block of boxes each: its cubes numbered in order of first entry, and each
  // of its entries' cube (the block's number) and rank among the block's entries in that cube.
  // Blocks of 4,096 boxes, a quarter of the light loops': a call with fewer boxes than a block
  // runs on one thread, and on the ball-plate to 2 µs half the calls enter fewer than 2,610.
  constexpr std::size_t block = 4096;
  const std::size_t blocks = parallel::block_count(n, block);
  if (g.blocks.size() < blocks) g.blocks.resize(blocks);
  parallel::for_blocks(
      n,
      [&](std::size_t blk, std::size_t begin, std::size_t end) {
        BlockCubes& b = g.blocks[blk];
        // Room for an eighth of the block's entries to start with (a cube holds several).
        b.table.reset(static_cast<std::size_t>(g.entry_begin[end] - g.entry_begin[begin]) / 8);
        b.key.clear();
        b.count.clear();
        std::size_t e = static_cast<std::size_t>(g.entry_begin[begin]);
        for (std::size_t i = begin; i < end; ++i) {
          const CubeRange& r = g.ranges[i];
          for (std::int64_t x = r.lo[0]; x <= r.hi[0]; ++x)
            for (std::int64_t y = r.lo[1]; y <= r.hi[1]; ++y)
              for (std::int64_t z = r.lo[2]; z <= r.hi[2]; ++z) {
                const std::uint64_t key = g.key(x, y, z);
                const Index fresh = static_cast<Index>(b.count.size());
                const Index c = b.table.insert(key, fresh);
                if (c == fresh) {
                  b.key.push_back(key);
                  b.count.push_back(0);
                  if (2 * b.key.size() > b.table.mask) b.table.grow();
                }
                g.rank[e] = b.count[c]++;
                g.entry_cube[e++] = c;
              }
        }
      },
      block);
  // Serial, block after block, a cube each (not an entry): the cubes numbered in order of first
  // entry over all the boxes, as one serial pass over the entries would, and the entries of
  // earlier blocks in each.
  std::size_t block_cubes = 0;
  for (std::size_t blk = 0; blk < blocks; ++blk) block_cubes += g.blocks[blk].key.size();
  g.table.reset(block_cubes);
  g.next.clear();
  for (std::size_t blk = 0; blk < blocks; ++blk) {
    BlockCubes& b = g.blocks[blk];
    b.global.resize(b.key.size());
    b.before.resize(b.key.size());
    for (std::size_t c = 0; c < b.key.size(); ++c) {
      const Index fresh = static_cast<Index>(g.next.size());
      const Index cube = g.table.insert(b.key[c], fresh);
      if (cube == fresh) g.next.push_back(0);
      b.global[c] = cube;
      b.before[c] = g.next[cube];
      g.next[cube] += b.count[c];
    }
  }
  const std::size_t cubes = g.next.size();
  g.start.resize(cubes + 1);
  g.start[0] = 0;
  for (std::size_t c = 0; c < cubes; ++c) g.start[c + 1] = g.start[c] + g.next[c];
  // Eight entries of padding (NaN boxes: no test passes), so that lanes may read past the last.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (auto* v : {&g.lox, &g.loy, &g.loz, &g.hix, &g.hiy, &g.hiz}) {
    v->resize(entries + kPad);
    std::fill(v->begin() + static_cast<std::ptrdiff_t>(entries), v->end(), nan);
  }
  g.first.resize(entries + kPad);
  std::fill(g.first.begin() + static_cast<std::ptrdiff_t>(entries), g.first.end(), 0);
  g.item.resize(entries);
  // On the threads: each box writes its own entries (their places known from the ranks), its
  // entries' cubes and ranks made the whole's.
  parallel::for_each(
      n,
      [&](std::size_t i) {
        const BlockCubes& blk = g.blocks[i / block];
        const CubeRange& r = g.ranges[i];
        const Box& b = boxes[i];
        const float lx = round_down(b.lo.x()), ly = round_down(b.lo.y()), lz = round_down(b.lo.z());
        const float ux = round_up(b.hi.x()), uy = round_up(b.hi.y()), uz = round_up(b.hi.z());
        Index k = g.entry_begin[i];
        for (std::int64_t x = r.lo[0]; x <= r.hi[0]; ++x)
          for (std::int64_t y = r.lo[1]; y <= r.hi[1]; ++y)
            for (std::int64_t z = r.lo[2]; z <= r.hi[2]; ++z, ++k) {
              const Index local = g.entry_cube[k];
              g.entry_cube[k] = blk.global[local];
              g.rank[k] += blk.before[local];
              const Index p = g.start[g.entry_cube[k]] + g.rank[k];
              g.lox[p] = lx;
              g.loy[p] = ly;
              g.loz[p] = lz;
              g.hix[p] = ux;
              g.hiy[p] = uy;
              g.hiz[p] = uz;
              g.first[p] = (x == r.lo[0] ? 1 : 0) | (y == r.lo[1] ? 2 : 0) | (z == r.lo[2] ? 4 : 0);
              g.item[p] = static_cast<Index>(i);
            }
      },
      block);
}

// A query: its float box rounded outward (l, u) and inward (sl, su), and the first-cube bits its
// partners must bring.
//
// An entry's float box b is rounded outward too, so the test b.lo <= u && b.hi >= l passes every
// pair whose double boxes overlap, and a few more. The strict test b.lo < su && b.hi > sl is
// sure: b.lo's double lies below the next float above b.lo, which is ≤ su ≤ the query's hi (and
// likewise above). Only the hits that are not sure need the double boxes.
struct Query {
  float lx, ly, lz, ux, uy, uz;
  float slx, sly, slz, sux, suy, suz;
  std::int32_t need;
};

Query query(const Box& b, std::int32_t need) {
  return {round_down(b.lo.x()),
          round_down(b.lo.y()),
          round_down(b.lo.z()),
          round_up(b.hi.x()),
          round_up(b.hi.y()),
          round_up(b.hi.z()),
          round_up(b.lo.x()),
          round_up(b.lo.y()),
          round_up(b.lo.z()),
          round_down(b.hi.x()),
          round_down(b.hi.y()),
          round_down(b.hi.z()),
          need};
}

// A hit written as its entry when sure, as ~entry (negative) when the double boxes must decide.
inline Index mark(Index q, bool sure) {
  return sure ? q : ~q;
}

// Entries [begin, end) tested one at a time: those whose float boxes overlap the query's and
// whose first-cube bits bring all of `need`'s, written (marked) to out in order; their count
// returned.
std::size_t scan_scalar(const Cubes& g, Index begin, Index end, const Query& w, Index* out) {
  std::size_t m = 0;
  for (Index q = begin; q < end; ++q)
    if ((g.lox[q] <= w.ux) & (g.hix[q] >= w.lx) & (g.loy[q] <= w.uy) & (g.hiy[q] >= w.ly) &
        (g.loz[q] <= w.uz) & (g.hiz[q] >= w.lz) & ((g.first[q] & w.need) == w.need))
      out[m++] = mark(q, (g.lox[q] < w.sux) & (g.hix[q] > w.slx) & (g.loy[q] < w.suy) &
                             (g.hiy[q] > w.sly) & (g.loz[q] < w.suz) & (g.hiz[q] > w.slz));
  return m;
}

#if defined(__x86_64__) && defined(__GNUC__)
// Entries [begin, end): those whose float boxes overlap the query's and whose first-cube bits
// bring all of `need`'s, written (marked) to out in order; their count returned. Eight entries at a
// time (AVX2, where the processor has it), the hits read from the comparison's sign bits, so that
// no branch is taken per entry (most of a cube's entries miss, and such a branch mispredicts).
// Comparisons are exact: the lanes change no answer.
__attribute__((target("avx2"))) std::size_t scan_avx2(const Cubes& g, Index begin, Index end,
                                                      const Query& w, Index* out) {
  const __m256 lx = _mm256_set1_ps(w.lx), ly = _mm256_set1_ps(w.ly), lz = _mm256_set1_ps(w.lz);
  const __m256 ux = _mm256_set1_ps(w.ux), uy = _mm256_set1_ps(w.uy), uz = _mm256_set1_ps(w.uz);
  const __m256 slx = _mm256_set1_ps(w.slx), sly = _mm256_set1_ps(w.sly),
               slz = _mm256_set1_ps(w.slz);
  const __m256 sux = _mm256_set1_ps(w.sux), suy = _mm256_set1_ps(w.suy),
               suz = _mm256_set1_ps(w.suz);
  const __m256i need = _mm256_set1_epi32(w.need);
  std::size_t m = 0;
  Index q = begin;
  for (; q < end; q += 8) {
    const __m256 ax = _mm256_loadu_ps(&g.lox[q]), bx = _mm256_loadu_ps(&g.hix[q]);
    const __m256 ay = _mm256_loadu_ps(&g.loy[q]), by = _mm256_loadu_ps(&g.hiy[q]);
    const __m256 az = _mm256_loadu_ps(&g.loz[q]), bz = _mm256_loadu_ps(&g.hiz[q]);
    __m256 ok = _mm256_and_ps(_mm256_cmp_ps(ax, ux, _CMP_LE_OQ), _mm256_cmp_ps(bx, lx, _CMP_GE_OQ));
    ok = _mm256_and_ps(ok, _mm256_cmp_ps(ay, uy, _CMP_LE_OQ));
    ok = _mm256_and_ps(ok, _mm256_cmp_ps(by, ly, _CMP_GE_OQ));
    ok = _mm256_and_ps(ok, _mm256_cmp_ps(az, uz, _CMP_LE_OQ));
    ok = _mm256_and_ps(ok, _mm256_cmp_ps(bz, lz, _CMP_GE_OQ));
    const __m256i bits =
        _mm256_and_si256(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(&g.first[q])), need);
    ok = _mm256_and_ps(ok, _mm256_castsi256_ps(_mm256_cmpeq_epi32(bits, need)));
    int mask = _mm256_movemask_ps(ok);
    if (end - q < 8) mask &= (1 << (end - q)) - 1;
    if (mask == 0) continue;
    __m256 sure =
        _mm256_and_ps(_mm256_cmp_ps(ax, sux, _CMP_LT_OQ), _mm256_cmp_ps(bx, slx, _CMP_GT_OQ));
    sure = _mm256_and_ps(sure, _mm256_cmp_ps(ay, suy, _CMP_LT_OQ));
    sure = _mm256_and_ps(sure, _mm256_cmp_ps(by, sly, _CMP_GT_OQ));
    sure = _mm256_and_ps(sure, _mm256_cmp_ps(az, suz, _CMP_LT_OQ));
    sure = _mm256_and_ps(sure, _mm256_cmp_ps(bz, slz, _CMP_GT_OQ));
    const int sure_mask = _mm256_movemask_ps(sure);
    for (; mask != 0; mask &= mask - 1) {
      const int k = __builtin_ctz(static_cast<unsigned>(mask));
      out[m++] = mark(q + k, (sure_mask >> k) & 1);
    }
  }
  return m;
}

// Four at a time (SSE2: every x86-64).
std::size_t scan_sse2(const Cubes& g, Index begin, Index end, const Query& w, Index* out) {
  const __m128 lx = _mm_set1_ps(w.lx), ly = _mm_set1_ps(w.ly), lz = _mm_set1_ps(w.lz);
  const __m128 ux = _mm_set1_ps(w.ux), uy = _mm_set1_ps(w.uy), uz = _mm_set1_ps(w.uz);
  const __m128 slx = _mm_set1_ps(w.slx), sly = _mm_set1_ps(w.sly), slz = _mm_set1_ps(w.slz);
  const __m128 sux = _mm_set1_ps(w.sux), suy = _mm_set1_ps(w.suy), suz = _mm_set1_ps(w.suz);
  const __m128i need = _mm_set1_epi32(w.need);
  std::size_t m = 0;
  Index q = begin;
  for (; q < end; q += 4) {
    const __m128 ax = _mm_loadu_ps(&g.lox[q]), bx = _mm_loadu_ps(&g.hix[q]);
    const __m128 ay = _mm_loadu_ps(&g.loy[q]), by = _mm_loadu_ps(&g.hiy[q]);
    const __m128 az = _mm_loadu_ps(&g.loz[q]), bz = _mm_loadu_ps(&g.hiz[q]);
    __m128 ok = _mm_and_ps(_mm_cmple_ps(ax, ux), _mm_cmpge_ps(bx, lx));
    ok = _mm_and_ps(ok, _mm_cmple_ps(ay, uy));
    ok = _mm_and_ps(ok, _mm_cmpge_ps(by, ly));
    ok = _mm_and_ps(ok, _mm_cmple_ps(az, uz));
    ok = _mm_and_ps(ok, _mm_cmpge_ps(bz, lz));
    const __m128i bits =
        _mm_and_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(&g.first[q])), need);
    ok = _mm_and_ps(ok, _mm_castsi128_ps(_mm_cmpeq_epi32(bits, need)));
    int mask = _mm_movemask_ps(ok);
    if (end - q < 4) mask &= (1 << (end - q)) - 1;
    if (mask == 0) continue;
    __m128 sure = _mm_and_ps(_mm_cmplt_ps(ax, sux), _mm_cmpgt_ps(bx, slx));
    sure = _mm_and_ps(sure, _mm_cmplt_ps(ay, suy));
    sure = _mm_and_ps(sure, _mm_cmpgt_ps(by, sly));
    sure = _mm_and_ps(sure, _mm_cmplt_ps(az, suz));
    sure = _mm_and_ps(sure, _mm_cmpgt_ps(bz, slz));
    const int sure_mask = _mm_movemask_ps(sure);
    for (; mask != 0; mask &= mask - 1) {
      const int k = __builtin_ctz(static_cast<unsigned>(mask));
      out[m++] = mark(q + k, (sure_mask >> k) & 1);
    }
  }
  return m;
}

#endif

// The lanes in use: 8 where the processor has AVX2, else 4 on x86-64, else 1.
int best_lanes() {
#if defined(__x86_64__) && defined(__GNUC__)
  return __builtin_cpu_supports("avx2") ? 8 : 4;
#else
  return 1;
#endif
}
std::atomic<int> lanes{best_lanes()};

std::size_t scan(const Cubes& g, Index begin, Index end, const Query& w, Index* out) {
#if defined(__x86_64__) && defined(__GNUC__)
  switch (lanes.load(std::memory_order_relaxed)) {
    case 8:
      return scan_avx2(g, begin, end, w, out);
    case 4:
      return scan_sse2(g, begin, end, w, out);
  }
#endif
  return scan_scalar(g, begin, end, w, out);
}

// One query's partners: a sorted run per cube, merged at the end (buffers kept between queries).
struct Partners {
  std::vector<Index> listed, near, scratch;
  std::vector<std::size_t> bounds{0};  // run r: near[bounds[r]..bounds[r + 1])
  void clear() {
    near.clear();
    bounds.assign(1, 0);
  }
  void merge() {
    for (std::size_t r = 2; r < bounds.size(); ++r) {
      scratch.resize(bounds[r]);
      std::merge(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(bounds[r - 1]),
                 near.begin() + static_cast<std::ptrdiff_t>(bounds[r - 1]),
                 near.begin() + static_cast<std::ptrdiff_t>(bounds[r]), scratch.begin());
      std::copy(scratch.begin(), scratch.end(), near.begin());
    }
  }
};

// The query's partners among entries [begin, end) of g, as one more run: the lanes' hits that
// are admissible and whose double boxes overlap (tested only where the float test was not sure;
// b is the query's box, boxes the entries' primitives').
template <class Admissible>
void partners(const Cubes& g, Index begin, Index end, const Query& w, const Box& b,
              const std::vector<Box>& boxes, Admissible&& admissible, Partners& run) {
  if (begin >= end) return;
  run.listed.resize(static_cast<std::size_t>(end - begin));
  const std::size_t m = scan(g, begin, end, w, run.listed.data());
  for (std::size_t h = 0; h < m; ++h) {
    const Index hit = run.listed[h];
    const Index o = g.item[hit < 0 ? ~hit : hit];
    if (admissible(o) && (hit >= 0 || boxes_overlap(b, boxes[o]))) run.near.push_back(o);
  }
  if (run.near.size() > run.bounds.back()) run.bounds.push_back(run.near.size());
}

void join(const std::vector<PairBlock>& blocks, std::vector<std::pair<Index, Index>>& out) {
  std::size_t n = 0;
  for (const auto& v : blocks) n += v.size();
  out.reserve(n);
  advise_huge_pages(out.data(), n * sizeof(out[0]));
  for (const auto& v : blocks) out.insert(out.end(), v.begin(), v.end());
}

class Grid : public Broadphase {
 public:
  explicit Grid(double cell) : cell_(cell) {}
  std::string name() const override { return "grid"; }
  Candidates find(const BroadphaseInput& in) override {
    auto t0 = Clock::now();
    // Cubes of twice the mean box size, for the faces and for the edges apart: the boxes of
    // particles (degenerate edges) are far smaller than faces', and a cube sized by the faces
    // put thousands of particles in one cube, all paired with each other.
    enter(faces_, in.face_box, cube_size(in.face_box, cell_));
    enter(edges_, in.edge_box, cube_size(in.edge_box, cell_));
    const Cubes& faces = faces_;
    const Cubes& edges = edges_;
    build_seconds = since(t0);
    t0 = Clock::now();
    Candidates c;
    const std::size_t nodes = in.node_box.size();
    auto& nf = blocks(parallel::block_count(nodes));
    parallel::for_blocks(nodes, [&](std::size_t blk, std::size_t begin, std::size_t end) {
      Partners run;
      for (std::size_t un = begin; un < end; ++un) {
        const Index n = static_cast<Index>(un);
        const Box& b = in.node_box[n];
        if (!b.lo.allFinite() || !b.hi.allFinite())
          throw std::invalid_argument("broadphase: node " + std::to_string(n) +
                                      " has a non-finite box");
        const CubeRange r = faces.range(b);
        // Only the cubes where faces are (a node's box may reach far beyond them).
        CubeRange in_span = r;
        for (int a = 0; a < 3; ++a) {
          in_span.lo[a] = std::max(r.lo[a], faces.origin[a]);
          in_span.hi[a] = std::min(r.hi[a], faces.origin[a] + faces.span[a] - 1);
        }
        Query w = query(b, 0);
        run.clear();
        for (std::int64_t x = in_span.lo[0]; x <= in_span.hi[0]; ++x)
          for (std::int64_t y = in_span.lo[1]; y <= in_span.hi[1]; ++y)
            for (std::int64_t z = in_span.lo[2]; z <= in_span.hi[2]; ++z) {
              const Index cube = faces.find(faces.key(x, y, z));
              if (cube < 0) continue;
              // The bits the face's entry must bring: the axes on which this is not the node's
              // first cube.
              const std::int32_t mine =
                  (x == r.lo[0] ? 1 : 0) | (y == r.lo[1] ? 2 : 0) | (z == r.lo[2] ? 4 : 0);
              const Index e0 = faces.start[cube], e1 = faces.start[cube + 1];
              w.need = 7 & ~mine;
              partners(
                  faces, e0, e1, w, b, in.face_box,
                  [&](Index f) { return admissible_node_face(in, n, f); }, run);
            }
        run.merge();
        for (const Index f : run.near) nf[blk].emplace_back(n, f);
      }
    });
    join(nf, c.node_face);
    const std::size_t ne = in.edge_box.size();
    auto& ee = blocks(parallel::block_count(ne));
    parallel::for_blocks(ne, [&](std::size_t blk, std::size_t begin, std::size_t end) {
      Partners run;
      for (std::size_t ua = begin; ua < end; ++ua) {
        const Index a = static_cast<Index>(ua);
        const Box& b = in.edge_box[a];
        Query w = query(b, 0);
        run.clear();
        for (Index k = edges.entry_begin[a]; k < edges.entry_begin[a + 1]; ++k) {
          const Index p = edges.start[edges.entry_cube[k]] + edges.rank[k];
          const Index e1 = edges.start[edges.entry_cube[k] + 1];
          w.need = 7 & ~edges.first[p];
          partners(
              edges, p + 1, e1, w, b, in.edge_box,
              [&](Index o) { return admissible_edge_edge(in, a, o); }, run);
        }
        run.merge();
        for (const Index o : run.near) ee[blk].emplace_back(a, o);
      }
    });
    join(ee, c.edge_edge);
    query_seconds = since(t0);
    if (!keep_memory) {
      faces_ = Cubes{};
      edges_ = Cubes{};
      blocks_ = {};
    }
    return c;
  }

 private:
  // n empty lists, one per block, kept between calls with their memory.
  std::vector<PairBlock>& blocks(std::size_t n) {
    if (blocks_.size() < n) blocks_.resize(n);
    for (auto& b : blocks_) b.clear();
    return blocks_;
  }
  double cell_;
  Cubes faces_, edges_;  // with keep_memory, kept between calls: the next call reuses them
  std::vector<PairBlock> blocks_;
};

}  // namespace

int set_grid_lanes(int n) {
  const int best = best_lanes();
  lanes = n <= 0 || n > best ? best : (n >= 8 ? 8 : n >= 4 ? 4 : 1);
  return lanes;
}

std::unique_ptr<Broadphase> make_grid_broadphase(double cell) {
  return std::make_unique<Grid>(cell);
}

}  // namespace tc
