#include "gradmpm/core/Ranks.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include "gradmpm/core/Plugins.hpp"

namespace gradmpm::ranks {

namespace {
struct State {
  std::unique_ptr<Backend> backend;  ///< MPI's collectives in a distributed run
  int size = 1, rank = 0, on_this_machine = 1;
  std::vector<std::function<void()>> hooks;
};
State& state() {
  static State s;
  return s;
}
/// The backend when there are several ranks (else the collectives are identities).
Backend* mpi() { return state().size > 1 ? state().backend.get() : nullptr; }
}  // namespace

int size() { return state().size; }
long long Neighbours::received() const {
  long long n = 0;
  for (const long long c : from_count) n += c;
  return n;
}
int rank() { return state().rank; }
int on_this_machine() { return state().on_this_machine; }
void before_stop(std::function<void()> hook) {
  if (state().backend) state().hooks.push_back(std::move(hook));
}

namespace {
/// One process writes the whole file and flushes it to disk.
std::string write_whole(const std::string& file, const std::string& bytes) {
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    if (out) out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (out) out.close();
    if (!out) return file + ": cannot write (" + std::strerror(errno) + ")";
  }
  const int fd = ::open(file.c_str(), O_RDONLY);
  const bool synced = fd >= 0 && ::fsync(fd) == 0;
  if (fd >= 0) ::close(fd);
  return synced ? "" : file + ": cannot flush to disk (" + std::strerror(errno) + ")";
}
}  // namespace

Session::Session(int* argc, char*** argv) {
  const auto start = plugin_function<StartBackend>("petsc", "gradmpm_start_mpi", "a run on several MPI ranks");
  State& s = state();
  s.backend.reset(start(argc, argv));
  s.size = s.backend->size();
  s.rank = s.backend->rank();
  s.on_this_machine = s.backend->on_this_machine();
}

Session::~Session() {
  State& s = state();
  for (auto it = s.hooks.rbegin(); it != s.hooks.rend(); ++it) (*it)();
  s.hooks.clear();
  s.backend.reset();  // MPI_Finalize
  s = State{};
}

// Serially every collective is the identity; with several ranks, MPI's (the backend's).
void sum(double* v, std::size_t n) {
  if (Backend* b = mpi()) b->sum(v, n);
}
int min(int value) { return mpi() ? mpi()->min(value) : value; }
void max(int* v, std::size_t n) {
  if (Backend* b = mpi()) b->max(v, n);
}
void max(double* v, std::size_t n) {
  if (Backend* b = mpi()) b->max(v, n);
}
std::vector<int> all_gather(const std::vector<int>& mine) { return mpi() ? mpi()->all_gather(mine) : mine; }
void all_gather_rows(const double* mine, const std::vector<int>& counts, double* all) {
  if (Backend* b = mpi()) return b->all_gather_rows(mine, counts, all);
  std::copy(mine, mine + counts[0], all);
}
Neighbours neighbours_of(const std::vector<long long>& send_counts) {
  if (Backend* b = mpi()) return b->neighbours_of(send_counts);
  Neighbours n;
  if (!send_counts.empty() && send_counts[0] > 0) {
    n.to = n.from = {0};
    n.to_count = n.from_count = {send_counts[0]};
  }
  return n;
}
std::vector<char> exchange(const Neighbours& n, const char* send, std::size_t item_bytes) {
  if (Backend* b = mpi()) return b->exchange(n, send, item_bytes);
  return std::vector<char>(send, send + static_cast<std::size_t>(n.received()) * item_bytes);
}
std::vector<std::string> gather_on_root(const std::string& mine) {
  return mpi() ? mpi()->gather_on_root(mine) : std::vector<std::string>{mine};
}
std::vector<char> broadcast(std::vector<char> bytes) { return mpi() ? mpi()->broadcast(std::move(bytes)) : bytes; }
void abort(int code) {
  if (state().backend) state().backend->abort(code);
  std::exit(code);
}
std::string write_in_rank_order(const std::string& file, const std::string& bytes) {
  return mpi() ? mpi()->write_in_rank_order(file, bytes) : write_whole(file, bytes);
}

std::string first_problem(const std::string& problem) {
  if (size() == 1) return problem;
  if (min(problem.empty() ? 1 : 0) == 1) return "";
  std::string first;
  for (const std::string& p : gather_on_root(problem))
    if (first.empty() && !p.empty()) first = p;
  const std::vector<char> told = broadcast(std::vector<char>(first.begin(), first.end()));
  return std::string(told.begin(), told.end());
}

}  // namespace gradmpm::ranks
