// MPI's collectives for core/Ranks.hpp, in the plugin libgradmpm_petsc.so (core/Plugins.hpp):
// Session loads it for a run on several ranks, so a serial process never loads MPI.
// The library calls these with more than one rank only.
#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "gradmpm/core/Ranks.hpp"

namespace gradmpm::ranks {

namespace {

class MpiBackend final : public Backend {
 public:
  MpiBackend(int* argc, char*** argv) {
    int provided = 0;
    // The point loops run on OpenMP threads; only the main thread calls MPI.
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm machine;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &machine);
    MPI_Comm_size(machine, &on_this_machine_);
    MPI_Comm_free(&machine);
    MPI_Comm_dup(MPI_COMM_WORLD, &exchange_comm_);
  }
  ~MpiBackend() override {
    MPI_Comm_free(&exchange_comm_);
    MPI_Finalize();
  }
  MpiBackend(const MpiBackend&) = delete;
  MpiBackend& operator=(const MpiBackend&) = delete;

  int size() const override { return size_; }
  int rank() const override { return rank_; }
  int on_this_machine() const override { return on_this_machine_; }

  void sum(double* v, std::size_t n) override {
    if (n == 0) return;
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

  int min(int value) override {
    MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    return value;
  }

  void max(int* v, std::size_t n) override {
    if (n > 0) MPI_Allreduce(MPI_IN_PLACE, v, static_cast<int>(n), MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  }

  void max(double* v, std::size_t n) override {
    if (n > 0) MPI_Allreduce(MPI_IN_PLACE, v, static_cast<int>(n), MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  }

  std::vector<int> all_gather(const std::vector<int>& mine) override {
    const int count = static_cast<int>(mine.size());
    std::vector<int> counts(size()), offsets(size(), 0);
    MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    std::partial_sum(counts.begin(), counts.end() - 1, offsets.begin() + 1);
    std::vector<int> all(static_cast<std::size_t>(offsets.back()) + counts.back());
    MPI_Allgatherv(mine.data(), count, MPI_INT, all.data(), counts.data(), offsets.data(), MPI_INT, MPI_COMM_WORLD);
    return all;
  }

  void all_gather_rows(const double* mine, const std::vector<int>& counts, double* all) override {
    std::vector<int> offsets(counts.size(), 0);
    std::partial_sum(counts.begin(), counts.end() - 1, offsets.begin() + 1);
    MPI_Allgatherv(mine, counts[rank()], MPI_DOUBLE, all, counts.data(), offsets.data(), MPI_DOUBLE, MPI_COMM_WORLD);
  }

  Neighbours neighbours_of(const std::vector<long long>& send_counts) override {
    Neighbours n;
    const int me = rank();
    for (int r = 0; r < static_cast<int>(send_counts.size()); ++r)
      if (send_counts[r] > 0) {
        n.to.push_back(r);
        n.to_count.push_back(send_counts[r]);
      }
    // Synchronous sends: one completes when its message was received, so a rank whose sends
    // all completed enters the barrier; when every rank has, no message is on its way.
    MPI_Comm comm = exchange_comm_;
    // A rank that saw this round's barrier complete may start the next round and send to a
    // rank that is still probing in this one: consecutive rounds use different tags (a
    // round after the next cannot start before this one has ended everywhere).
    const int tag = 1 + 2 * (rounds_++ % 2);  // 1, 3, 1, ... (the data's tag is 2)
    std::vector<MPI_Request> sends;
    for (std::size_t k = 0; k < n.to.size(); ++k)
      if (n.to[k] != me) {
        sends.emplace_back();
        MPI_Issend(&n.to_count[k], 1, MPI_LONG_LONG, n.to[k], tag, comm, &sends.back());
      }
    std::vector<std::pair<int, long long>> got;
    if (send_counts.size() > static_cast<std::size_t>(me) && send_counts[me] > 0) got.emplace_back(me, send_counts[me]);
    MPI_Request barrier = MPI_REQUEST_NULL;
    bool in_barrier = false;
    for (;;) {
      int arrived = 0;
      MPI_Status status;
      MPI_Iprobe(MPI_ANY_SOURCE, tag, comm, &arrived, &status);
      if (arrived) {
        long long count = 0;
        MPI_Recv(&count, 1, MPI_LONG_LONG, status.MPI_SOURCE, tag, comm, MPI_STATUS_IGNORE);
        got.emplace_back(status.MPI_SOURCE, count);
      }
      int done = 0;
      if (!in_barrier) {
        MPI_Testall(static_cast<int>(sends.size()), sends.data(), &done, MPI_STATUSES_IGNORE);
        if (done) {
          MPI_Ibarrier(comm, &barrier);
          in_barrier = true;
        }
      } else {
        MPI_Test(&barrier, &done, MPI_STATUS_IGNORE);
        if (done) break;
      }
    }
    std::sort(got.begin(), got.end());
    for (const auto& [r, count] : got) {
      n.from.push_back(r);
      n.from_count.push_back(count);
    }
    return n;
  }

  std::vector<char> exchange(const Neighbours& n, const char* send, std::size_t item_bytes) override {
    std::vector<char> received(static_cast<std::size_t>(n.received()) * item_bytes);
    const int me = rank();
    auto bytes = [&](long long items) {
      const long long b = items * static_cast<long long>(item_bytes);
      if (b > INT32_MAX) throw std::length_error("ranks::exchange: more than 2 GiB to one rank");
      return static_cast<int>(b);
    };
    MPI_Comm comm = exchange_comm_;
    constexpr int tag = 2;
    std::vector<MPI_Request> requests;
    const char* own = nullptr;
    char* own_to = nullptr;
    long long own_items = 0;
    std::size_t at = 0;
    for (std::size_t k = 0; k < n.from.size(); ++k) {
      if (n.from[k] == me) {
        own_to = received.data() + at;
      } else {
        requests.emplace_back();
        MPI_Irecv(received.data() + at, bytes(n.from_count[k]), MPI_BYTE, n.from[k], tag, comm, &requests.back());
      }
      at += static_cast<std::size_t>(n.from_count[k]) * item_bytes;
    }
    at = 0;
    for (std::size_t k = 0; k < n.to.size(); ++k) {
      if (n.to[k] == me) {
        own = send + at;
        own_items = n.to_count[k];
      } else {
        requests.emplace_back();
        MPI_Isend(send + at, bytes(n.to_count[k]), MPI_BYTE, n.to[k], tag, comm, &requests.back());
      }
      at += static_cast<std::size_t>(n.to_count[k]) * item_bytes;
    }
    if (own) std::memcpy(own_to, own, static_cast<std::size_t>(own_items) * item_bytes);
    MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
    return received;
  }

  std::vector<std::string> gather_on_root(const std::string& mine) override {
    const int count = static_cast<int>(mine.size());
    std::vector<int> counts(rank() == 0 ? size() : 0), offsets(counts.size(), 0);
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (rank() == 0) std::partial_sum(counts.begin(), counts.end() - 1, offsets.begin() + 1);
    std::string all(rank() == 0 ? static_cast<std::size_t>(offsets.back()) + counts.back() : 0, '\0');
    MPI_Gatherv(mine.data(), count, MPI_CHAR, all.data(), counts.data(), offsets.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
    std::vector<std::string> out;
    for (std::size_t r = 0; r < counts.size(); ++r) out.push_back(all.substr(offsets[r], counts[r]));
    return out;
  }

  std::vector<char> broadcast(std::vector<char> bytes) override {
    long long n = static_cast<long long>(bytes.size());
    MPI_Bcast(&n, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
    bytes.resize(static_cast<std::size_t>(n));
    MPI_Bcast(bytes.data(), static_cast<int>(n), MPI_CHAR, 0, MPI_COMM_WORLD);
    return bytes;
  }

  [[noreturn]] void abort(int code) override {
    MPI_Abort(MPI_COMM_WORLD, code);
    std::exit(code);
  }

  std::string write_in_rank_order(const std::string& file, const std::string& bytes) override {
    long long n = static_cast<long long>(bytes.size()), offset = 0, total = 0;
    MPI_Exscan(&n, &offset, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    if (rank() == 0) offset = 0;  // (MPI_Exscan leaves rank 0's undefined)
    MPI_Allreduce(&n, &total, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    auto problem = [&](const char* what, int code) {
      char text[MPI_MAX_ERROR_STRING];
      int length = 0;
      MPI_Error_string(code, text, &length);
      return file + ": " + what + " (" + std::string(text, length) + ")";
    };
    MPI_File fh;
    // Collective: every rank opens, or none (MPI-IO agrees on the outcome).
    int code = MPI_File_open(MPI_COMM_WORLD, file.c_str(), MPI_MODE_CREATE | MPI_MODE_WRONLY, MPI_INFO_NULL, &fh);
    if (code != MPI_SUCCESS) return problem("cannot open for writing", code);
    std::string result;
    code = MPI_File_set_size(fh, total);  // (collective) a file that was there is cut to this size
    if (code != MPI_SUCCESS) result = problem("cannot set its size", code);
    constexpr long long chunk = 1LL << 30;  // MPI counts are int
    for (long long at = 0; result.empty() && at < n; at += chunk) {
      const int count = static_cast<int>(std::min(chunk, n - at));
      MPI_Status status;
      code = MPI_File_write_at(fh, offset + at, bytes.data() + at, count, MPI_BYTE, &status);
      int written = 0;
      if (code == MPI_SUCCESS) MPI_Get_count(&status, MPI_BYTE, &written);
      if (code != MPI_SUCCESS || written != count) result = problem("cannot write", code);
    }
    code = MPI_File_sync(fh);  // (collective)
    if (code != MPI_SUCCESS && result.empty()) result = problem("cannot flush to disk", code);
    MPI_File_close(&fh);
    return result;
  }

 private:
  int size_ = 1, rank_ = 0, on_this_machine_ = 1;
  MPI_Comm exchange_comm_ = MPI_COMM_NULL;  ///< the sparse exchanges' messages, apart from any other
  long long rounds_ = 0;                    ///< neighbours_of calls so far (the same on every rank)
};

}  // namespace

}  // namespace gradmpm::ranks

extern "C" gradmpm::ranks::Backend* gradmpm_start_mpi(int* argc, char*** argv) {
  return new gradmpm::ranks::MpiBackend(argc, argv);
}
