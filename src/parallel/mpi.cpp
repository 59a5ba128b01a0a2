#include "tetcontact/parallel/mpi.hpp"

#include <mpi.h>

#include <chrono>
#include <cstdlib>
#include <limits>
#include <stdexcept>

namespace tc::mpi {
namespace {

bool joined = false;
int my_rank = 0, my_ranks = 1, my_local_ranks = 1;
double spent = 0.0;

// Times a collective into `spent`.
class Timed {
 public:
  Timed() : start_(std::chrono::steady_clock::now()) {}
  ~Timed() {
    spent += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

void check(int rc, const char* what) {
  if (rc != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

}  // namespace

int launched_size() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (const char* size = std::getenv(var)) return std::max(1, std::atoi(size));
  return 1;
}

void init(int* argc, char*** argv) {
  if (joined || launched_size() <= 1) return;
  int provided = 0;
  check(MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  joined = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &my_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &my_ranks);
  MPI_Comm local;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, my_rank, MPI_INFO_NULL, &local);
  MPI_Comm_size(local, &my_local_ranks);
  MPI_Comm_free(&local);
}

void finalize() {
  if (!joined) return;
  MPI_Finalize();
  joined = false;
}

int rank() {
  return my_rank;
}

int ranks() {
  return my_ranks;
}

int local_ranks() {
  return my_local_ranks;
}

std::pair<std::size_t, std::size_t> slice(std::size_t n) {
  const auto r = static_cast<std::size_t>(my_rank), ranks = static_cast<std::size_t>(my_ranks);
  return {n * r / ranks, n * (r + 1) / ranks};
}

std::vector<char> all_gather(const std::vector<char>& mine) {
  if (!joined) return mine;
  return all_gather(mine, all_gather_value(mine.size()));
}

std::vector<char> all_gather(const std::vector<char>& mine, const std::vector<std::size_t>& sizes) {
  if (!joined) return mine;
  Timed t;
  if (sizes.size() != static_cast<std::size_t>(my_ranks) || sizes[my_rank] != mine.size())
    throw std::runtime_error("MPI: a gather's sizes do not match this rank's piece");
  std::vector<int> counts(my_ranks), displs(my_ranks);
  long total = 0;
  for (int r = 0; r < my_ranks; ++r) {
    if (total + static_cast<long>(sizes[r]) > std::numeric_limits<int>::max())
      throw std::runtime_error("MPI: a gather of over 2 GiB");
    counts[r] = static_cast<int>(sizes[r]);
    displs[r] = static_cast<int>(total);
    total += counts[r];
  }
  std::vector<char> all(static_cast<std::size_t>(total));
  check(MPI_Allgatherv(mine.data(), counts[my_rank], MPI_BYTE, all.data(), counts.data(),
                       displs.data(), MPI_BYTE, MPI_COMM_WORLD),
        "MPI_Allgatherv");
  return all;
}

long max(long mine) {
  if (!joined) return mine;
  Timed t;
  long out = 0;
  check(MPI_Allreduce(&mine, &out, 1, MPI_LONG, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
  return out;
}

double max(double mine) {
  if (!joined) return mine;
  Timed t;
  double out = 0;
  check(MPI_Allreduce(&mine, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
  return out;
}

std::string broadcast(const std::string& text, int root) {
  if (!joined) return text;
  Timed t;
  long size = my_rank == root ? static_cast<long>(text.size()) : 0;
  check(MPI_Bcast(&size, 1, MPI_LONG, root, MPI_COMM_WORLD), "MPI_Bcast");
  std::string out = my_rank == root ? text : std::string(static_cast<std::size_t>(size), '\0');
  check(MPI_Bcast(out.data(), static_cast<int>(size), MPI_BYTE, root, MPI_COMM_WORLD), "MPI_Bcast");
  return out;
}

void abort(int code) {
  if (joined) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

double seconds() {
  return spent;
}

}  // namespace tc::mpi
