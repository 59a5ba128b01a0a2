// Threads on one machine, deterministic by construction (oneTBB underneath, in parallel.cpp only).
//
// Work is cut into blocks of a fixed size that does not depend on the thread count; a block's
// result is combined with the others' in block order. So a sum, a minimum with its argument
// or a list built over blocks is the same for 1, 2 or 16 threads, bit for bit: the schedule
// decides only who computes a block, never what it computes. Nothing here writes to memory
// that another block writes (no racing scatter): a loop that would scatter writes per item and
// gathers afterwards (see element.cpp's node–tet incidence).
#pragma once

#include <algorithm>
#include <cstddef>
#include <exception>
#include <functional>
#include <utility>
#include <vector>

namespace tc::parallel {

/// The number of threads the parallel loops use (≥ 1).
int threads();
/// Sets it; n ≤ 0 means all the cores the machine reports.
void set_threads(int n);
/// The cores the machine reports.
int hardware_threads();

/// Items per block: fixed, so that block boundaries never depend on the thread count.
inline constexpr std::size_t k_block = 1024;
/// Blocks for loops of a few nanoseconds an item (the nodes' updates, the boxes of a step):
/// a task of a thousand such items costs more to hand out than to run (the commit of bars'
/// 4,050 nodes took 3× longer on 2 threads than on one).
inline constexpr std::size_t k_light_block = 16384;

inline std::size_t block_count(std::size_t n, std::size_t block = k_block) {
  return (n + block - 1) / block;
}

/// Runs block(b) for every b in [0, blocks) on the threads, each b once (oneTBB's
/// work-stealing scheduler, whose idle workers sleep: several runs on one machine share its
/// cores instead of spinning against each other).
void run_blocks(std::size_t blocks, const std::function<void(std::size_t)>& block);

/// Sorts pairs ascending on the threads (a sort's result does not depend on the schedule).
void sort_pairs(std::vector<std::pair<int, int>>& pairs);

/// Runs body(block, begin, end) for every block of [0, n), blocks spread over the threads.
/// An exception thrown in a block is rethrown after the loop: the one of the lowest block, which
/// is what a serial loop would have thrown first. Blocks after a failing one may have run.
template <class Body>
void for_blocks(std::size_t n, Body&& body, std::size_t block = k_block) {
  const std::size_t blocks = block_count(n, block);
  if (blocks == 0) return;
  if (blocks == 1 || threads() == 1) {
    for (std::size_t b = 0; b < blocks; ++b) body(b, b * block, std::min(n, (b + 1) * block));
    return;
  }
  std::vector<std::exception_ptr> errors(blocks);
  run_blocks(blocks, [&](std::size_t b) {
    try {
      body(b, b * block, std::min(n, (b + 1) * block));
    } catch (...) {
      errors[b] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

/// Runs item(i) for every i in [0, n): for items that write only their own outputs.
template <class Item>
void for_each(std::size_t n, Item&& item, std::size_t block = k_block) {
  for_blocks(
      n,
      [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) item(i);
      },
      block);
}

/// Σ over blocks of block_value(begin, end), added in block order: a sum whose rounding is the
/// same for any thread count. T needs T{} (zero) and +=.
template <class T, class BlockValue>
T sum_blocks(std::size_t n, BlockValue&& block_value, std::size_t block = k_block) {
  std::vector<T> partial(block_count(n, block), T{});
  for_blocks(
      n,
      [&](std::size_t b, std::size_t begin, std::size_t end) {
        partial[b] = block_value(begin, end);
      },
      block);
  T total{};
  for (const T& p : partial) total += p;
  return total;
}

}  // namespace tc::parallel
