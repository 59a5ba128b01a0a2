// oneTBB is confined to this file: an arena of the requested size, and one task per block.
#include "tetcontact/parallel/parallel.hpp"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <memory>

namespace tc::parallel {

namespace {
int g_threads = 0;  // 0: not set yet (all cores)
std::unique_ptr<tbb::global_control> g_limit;
std::unique_ptr<tbb::task_arena> g_arena;

// An arena of the requested size; more threads than cores are allowed when asked for (TBB
// otherwise caps its workers at the cores, and "3 threads" on 2 cores would run 2).
tbb::task_arena& arena() {
  if (!g_arena || g_arena->max_concurrency() != threads()) {
    g_arena.reset();
    g_limit = std::make_unique<tbb::global_control>(
        tbb::global_control::max_allowed_parallelism,
        static_cast<std::size_t>(std::max(threads(), hardware_threads())));
    g_arena = std::make_unique<tbb::task_arena>(threads());
  }
  return *g_arena;
}
}  // namespace

int hardware_threads() {
  return std::max(1, tbb::info::default_concurrency());
}

int threads() {
  return g_threads > 0 ? g_threads : hardware_threads();
}

void set_threads(int n) {
  g_threads = n > 0 ? n : hardware_threads();
}

void run_blocks(std::size_t blocks, const std::function<void(std::size_t)>& block) {
  arena().execute([&] {
    // One block a task (simple_partitioner, grain 1): which thread runs a block never changes
    // what it computes, and the blocks are coarse enough (k_block items) to amortise a task.
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, blocks, 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t b = r.begin(); b < r.end(); ++b) block(b);
        },
        tbb::simple_partitioner());
  });
}

void sort_pairs(std::vector<std::pair<int, int>>& pairs) {
  if (threads() == 1 || pairs.size() < 100'000) {
    std::sort(pairs.begin(), pairs.end());
    return;
  }
  arena().execute([&] { tbb::parallel_sort(pairs.begin(), pairs.end()); });
}

}  // namespace tc::parallel
