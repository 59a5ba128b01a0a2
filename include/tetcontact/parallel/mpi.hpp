// Processes: OpenMPI underneath, in mpi.cpp only; nothing else includes <mpi.h>.
//
// The program joins an MPI job only when a launcher started it (mpirun, srun: the variables
// OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_SIZE name a size); otherwise it makes no MPI call at
// all and is one process (rank 0 of 1), and every function here is the identity or a no-op.
//
// Every collective here gives each rank the same result, whatever the order in which the
// messages arrive: gathers concatenate in rank order, minima break ties by the lowest index.
// A sum of doubles across ranks is not offered: its rounding would depend on how the work is
// cut (the solver gathers the terms and adds them in the serial order instead).
#pragma once

#include <cstddef>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "tetcontact/parallel/parallel.hpp"

namespace tc::mpi {

/// The size a launcher announced in the environment (1 when none did).
int launched_size();

/// Joins the job when launched_size() > 1 (MPI_Init_thread, funneled); call first in main.
void init(int* argc, char*** argv);
/// Leaves it (MPI_Finalize), if joined.
void finalize();

int rank();         // this process, 0 when not in a job
int ranks();        // the processes of the job, 1 when not in a job
int local_ranks();  // the processes of the job on this machine (sharing its cores)

/// This rank's share [first, last) of n items cut into equal consecutive slices in rank order
/// (all of them when not in a job): gathering the slices' results in rank order gives them
/// in item order.
std::pair<std::size_t, std::size_t> slice(std::size_t n);

/// Every rank's bytes, concatenated in rank order.
std::vector<char> all_gather(const std::vector<char>& mine);

/// The same when every rank knows every rank's size (sizes[r] bytes from rank r; mine holds
/// sizes[rank()]): one collective instead of two.
std::vector<char> all_gather(const std::vector<char>& mine, const std::vector<std::size_t>& sizes);

/// One value from every rank, in rank order (one collective).
template <class T>
std::vector<T> all_gather_value(const T& mine) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::vector<char> bytes(sizeof(T));
  std::memcpy(bytes.data(), &mine, sizeof(T));
  const std::vector<char> all = all_gather(bytes, std::vector<std::size_t>(ranks(), sizeof(T)));
  std::vector<T> out(all.size() / sizeof(T));
  std::memcpy(static_cast<void*>(out.data()), all.data(), all.size());
  return out;
}

/// item(i) for every i of this rank's slice of [0, out.size()), on the threads, each writing
/// out[i] alone; in a job the slices are then gathered in rank order, so every rank holds
/// every result, the ones one process computes. A collective: every rank calls it alike.
template <class T, class Item>
void for_each_sliced(std::vector<T>& out, Item&& item) {
  static_assert(std::is_trivially_copyable_v<T>);
  const auto [first, last] = slice(out.size());
  parallel::for_each(last - first, [&](std::size_t i) { item(first + i); });
  if (ranks() == 1) return;
  std::vector<char> mine((last - first) * sizeof(T));
  if (!mine.empty()) std::memcpy(mine.data(), out.data() + first, mine.size());
  const std::vector<char> all = all_gather(mine);
  if (!all.empty()) std::memcpy(out.data(), all.data(), all.size());
}

/// The largest value over the ranks (integers: exact whatever the order).
long max(long mine);
double max(double mine);

/// `text` as the root rank has it, on every rank.
std::string broadcast(const std::string& text, int root);

/// Ends every process of the job with `code` (MPI_Abort), after what this one printed.
[[noreturn]] void abort(int code);

/// Seconds spent in this file's collectives by this process since init.
double seconds();

}  // namespace tc::mpi
