#pragma once
// The MPI ranks of a distributed run (`mpirun -n N gradmpm run ...`, docs/parallel.md)
// and the few collective operations the driver needs. Without an MPI session (a serial run, a
// test program, a build without PETSc and MPI) there is one rank and every operation is
// the identity, so serial code calls them unconditionally.
//
// Each rank owns the points in its box of the grid's cells (mpm/PointMigration.hpp, issue
// 14): a load step and the gradient step work on them only (their stencils, Newton's point
// loops, the sparse matrices' shares, which PETSc adds up and splits the linear solves
// of), and after each converged step the points that moved into another rank's cells are
// sent to it. Everything else runs identically on every rank. Sums are reduced to rank 0
// and broadcast, so every rank sees the same bits and takes the same branches (a Newton
// decision never differs between ranks). A load step's vectors hold the rows each rank
// owns or reads only, summed between neighbours (solver/RowHalo.hpp).
#include <cstddef>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm::ranks {

/// Ranks of the MPI session (1 when none is started).
int size();
/// This process's rank (0 when none is started).
int rank();
inline bool distributed() { return size() > 1; }
/// Ranks of the MPI session on this process's machine (MPI_COMM_TYPE_SHARED; 1 when none is started).
int on_this_machine();

/// MPI started for the life of main when this process was launched as one of several
/// ranks (app/MpiLaunch.hpp), from the plugin libgradmpm_petsc.so (core/Plugins.hpp);
/// stopped, after the hooks of before_stop(), by the destructor.
class Session {
 public:
  Session(int* argc, char*** argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

/// Work to do before MPI stops (PETSc's finalisation, which must precede MPI's).
void before_stop(std::function<void()> hook);

/// v = the sum over ranks of v, the same bits on every rank.
void sum(double* v, std::size_t n);
/// The smallest of the ranks' values, on every rank.
int min(int value);
/// v = the entrywise largest over ranks of v, on every rank.
void max(int* v, std::size_t n);
void max(double* v, std::size_t n);
/// Whether `mine` holds on some rank, on every rank.
inline bool any(bool mine) {
  int v = mine ? 1 : 0;
  max(&v, 1);
  return v != 0;
}

/// Every rank's `mine`, concatenated in rank order, on every rank.
std::vector<int> all_gather(const std::vector<int>& mine);

/// The ranks' local rows [offset_r, offset_r + count_r) of a vector of sum(counts)
/// values, gathered on every rank; `counts` known to all.
void all_gather_rows(const double* mine, const std::vector<int>& counts, double* all);

/// The ranks a sparse exchange sends to and receives from, and how many items each (this
/// rank among them where it keeps items), in increasing rank.
struct Neighbours {
  std::vector<int> to, from;
  std::vector<long long> to_count, from_count;
  long long received() const;  ///< items this rank receives, its own included
  /// The same neighbours the other way: answers back to the ranks that sent.
  Neighbours reversed() const { return {from, to, from_count, to_count}; }
};

/// Finds who sends to this rank when send_counts[r] items go to rank r, without an
/// all-to-all: each rank sends its counts only to the ranks it sends to and takes the
/// messages that arrive until a non-blocking barrier, entered once its own were received,
/// completes (the NBX consensus of Hoefler, Siebert and Lumsdaine, PPoPP 2010). The cost
/// grows with the number of neighbours and log P, not with P. A collective call.
Neighbours neighbours_of(const std::vector<long long>& send_counts);

/// Sends items of `item_bytes` to the neighbours: `send` holds them grouped by
/// destination in rank order (n.to_count each); returns the items received, grouped by
/// source in rank order (n.from_count each). Point-to-point messages to the neighbours only.
std::vector<char> exchange(const Neighbours& n, const char* send, std::size_t item_bytes);

/// exchange() of typed items (plain data, copied bytewise).
template <class T>
std::vector<T> exchange(const Neighbours& n, const std::vector<T>& send) {
  static_assert(std::is_trivially_copyable_v<T>, "ranks::exchange sends items as bytes");
  const std::vector<char> got = exchange(n, reinterpret_cast<const char*>(send.data()), sizeof(T));
  std::vector<T> received(got.size() / sizeof(T));
  if (!got.empty()) std::memcpy(static_cast<void*>(received.data()), got.data(), got.size());
  return received;
}

/// What send_to() sent and received: `sent` the items in rank order of destination (the
/// order in which answers come back through `with.reversed()`), `received` the items
/// that came, grouped by source in rank order.
template <class T>
struct Sent {
  Neighbours with;
  std::vector<T> sent, received;
};

/// Sends to[r] to rank r (to[me] kept) to the ranks with items only (neighbours_of: no
/// all-to-all). A collective call.
template <class T>
Sent<T> send_to(const std::vector<std::vector<T>>& to) {
  Sent<T> s;
  std::vector<long long> count(to.size());
  for (std::size_t r = 0; r < to.size(); ++r) {
    count[r] = static_cast<long long>(to[r].size());
    s.sent.insert(s.sent.end(), to[r].begin(), to[r].end());
  }
  s.with = neighbours_of(count);
  s.received = ranks::exchange(s.with, s.sent);
  return s;
}

/// The answers (one per item received) to the items s.received, back to their senders:
/// one per item of s.sent, in its order. A collective call.
template <class T, class A>
std::vector<A> answer(const Sent<T>& s, const std::vector<A>& answers) {
  if (answers.size() != s.received.size()) throw std::logic_error("ranks::answer: one answer per item received expected");
  std::vector<A> back = ranks::exchange(s.with.reversed(), answers);
  if (back.size() != s.sent.size()) throw std::logic_error("ranks::answer: the answers do not match the items sent");
  return back;
}

/// Every rank's `mine` on rank 0, in rank order (empty on the other ranks).
std::vector<std::string> gather_on_root(const std::string& mine);

/// Rank 0's message on every rank (a decision only rank 0 could make:
/// whether the output folder can be written).
std::vector<char> broadcast(std::vector<char> bytes);

/// Stops every rank with `code` (an error that other ranks cannot know of).
[[noreturn]] void abort(int code);

/// Writes every rank's `bytes` into `file`, one after another in rank order: each rank
/// writes its own part at the offset of the ranks before it (MPI-IO; serially a plain
/// file), and the file is flushed to disk. A collective call; `file` is created, or
/// replaced. Returns "" or what went wrong on this rank.
std::string write_in_rank_order(const std::string& file, const std::string& bytes);

/// The first rank's non-empty `problem` (in rank order) on every rank, "" when no rank has one.
std::string first_problem(const std::string& problem);

/// Every rank stops with the first rank's problem when any rank has one: in a distributed
/// run as a UserError with that one message on every rank (rank 0 prints it; every rank
/// exits with code 2 and none waits for another that stopped); serially as E.
template <class E>
void stop_if_any(const std::string& problem) {
  if (!distributed()) {
    if (!problem.empty()) throw E(problem);
    return;
  }
  const std::string first = first_problem(problem);
  if (!first.empty()) throw UserError(first);
}

/// The collectives of a distributed run: MPI's, from the plugin (parallel/MpiRanks.cpp),
/// installed by Session. The functions above call it only when there are several ranks;
/// with one they are the identities. Deleting it stops MPI.
class Backend {
 public:
  virtual ~Backend() = default;
  virtual int size() const = 0;
  virtual int rank() const = 0;
  virtual int on_this_machine() const = 0;
  virtual void sum(double* v, std::size_t n) = 0;
  virtual int min(int value) = 0;
  virtual void max(int* v, std::size_t n) = 0;
  virtual void max(double* v, std::size_t n) = 0;
  virtual std::vector<int> all_gather(const std::vector<int>& mine) = 0;
  virtual void all_gather_rows(const double* mine, const std::vector<int>& counts, double* all) = 0;
  virtual Neighbours neighbours_of(const std::vector<long long>& send_counts) = 0;
  virtual std::vector<char> exchange(const Neighbours& n, const char* send, std::size_t item_bytes) = 0;
  virtual std::vector<std::string> gather_on_root(const std::string& mine) = 0;
  virtual std::vector<char> broadcast(std::vector<char> bytes) = 0;
  [[noreturn]] virtual void abort(int code) = 0;
  virtual std::string write_in_rank_order(const std::string& file, const std::string& bytes) = 0;
};

/// The plugin's entry point (extern "C" gradmpm_start_mpi): starts MPI with the
/// command line and returns its backend.
using StartBackend = Backend* (*)(int* argc, char*** argv);

}  // namespace gradmpm::ranks
