#include "gradmpm/core/Ranks.hpp"

#include <algorithm>
#include <cstdlib>
#include <numeric>

#ifdef GRADMPM_WITH_PETSC  // PETSc brings MPI: the distributed run needs both
#include <mpi.h>
#endif

namespace gradmpm::ranks {

namespace {
struct State {
  bool started = false;
  int size = 1, rank = 0;
  std::vector<std::function<void()>> hooks;
};
State& state() {
  static State s;
  return s;
}
}  // namespace

int size() { return state().size; }
int rank() { return state().rank; }
void before_stop(std::function<void()> hook) {
  if (state().started) state().hooks.push_back(std::move(hook));
}

#ifdef GRADMPM_WITH_PETSC

Session::Session(int* argc, char*** argv) {
  int provided = 0;
  // The point loops run on OpenMP threads; only the main thread calls MPI.
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  State& s = state();
  s.started = true;
  MPI_Comm_size(MPI_COMM_WORLD, &s.size);
  MPI_Comm_rank(MPI_COMM_WORLD, &s.rank);
}

Session::~Session() {
  State& s = state();
  for (auto it = s.hooks.rbegin(); it != s.hooks.rend(); ++it) (*it)();
  s.hooks.clear();
  MPI_Finalize();
  s = State{};
}

void sum(double* v, std::size_t n) {
  if (size() == 1 || n == 0) return;
  // Reduce, then broadcast: MPI_Allreduce may add in a different order on different ranks.
  constexpr std::size_t chunk = std::size_t(1) << 26;  // MPI counts are int
  for (std::size_t at = 0; at < n; at += chunk) {
    const int count = static_cast<int>(std::min(chunk, n - at));
    if (rank() == 0)
      MPI_Reduce(MPI_IN_PLACE, v + at, count, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    else
      MPI_Reduce(v + at, nullptr, count, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    MPI_Bcast(v + at, count, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  }
}

int min(int value) {
  if (size() > 1) MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return value;
}

void max(int* v, std::size_t n) {
  if (size() > 1 && n > 0) MPI_Allreduce(MPI_IN_PLACE, v, static_cast<int>(n), MPI_INT, MPI_MAX, MPI_COMM_WORLD);
}

void max(double* v, std::size_t n) {
  if (size() > 1 && n > 0) MPI_Allreduce(MPI_IN_PLACE, v, static_cast<int>(n), MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
}

std::vector<int> all_gather(const std::vector<int>& mine) {
  if (size() == 1) return mine;
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(size()), offsets(size(), 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  std::partial_sum(counts.begin(), counts.end() - 1, offsets.begin() + 1);
  std::vector<int> all(static_cast<std::size_t>(offsets.back()) + counts.back());
  MPI_Allgatherv(mine.data(), count, MPI_INT, all.data(), counts.data(), offsets.data(), MPI_INT, MPI_COMM_WORLD);
  return all;
}

void all_gather_rows(const double* mine, const std::vector<int>& counts, double* all) {
  std::vector<int> offsets(counts.size(), 0);
  std::partial_sum(counts.begin(), counts.end() - 1, offsets.begin() + 1);
  if (size() == 1) {
    std::copy(mine, mine + counts[0], all);
    return;
  }
  MPI_Allgatherv(mine, counts[rank()], MPI_DOUBLE, all, counts.data(), offsets.data(), MPI_DOUBLE, MPI_COMM_WORLD);
}

std::vector<char> broadcast(std::vector<char> bytes) {
  if (size() == 1) return bytes;
  long long n = static_cast<long long>(bytes.size());
  MPI_Bcast(&n, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  bytes.resize(static_cast<std::size_t>(n));
  MPI_Bcast(bytes.data(), static_cast<int>(n), MPI_CHAR, 0, MPI_COMM_WORLD);
  return bytes;
}

void abort(int code) {
  if (state().started) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

#else  // one rank: every collective is the identity

Session::Session(int*, char***) {}
Session::~Session() {
  for (auto& hook : state().hooks) hook();
}
void sum(double*, std::size_t) {}
int min(int value) { return value; }
void max(int*, std::size_t) {}
void max(double*, std::size_t) {}
std::vector<int> all_gather(const std::vector<int>& mine) { return mine; }
void all_gather_rows(const double* mine, const std::vector<int>& counts, double* all) {
  std::copy(mine, mine + counts[0], all);
}
std::vector<char> broadcast(std::vector<char> bytes) { return bytes; }
void abort(int code) { std::exit(code); }

#endif

}  // namespace gradmpm::ranks
