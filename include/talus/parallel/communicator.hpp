#pragma once
// The ranks of a distributed run (mpirun -np N talus ...) and the few collective operations the
// solver needs. A run started without mpirun never touches MPI: world() is then one rank and
// every operation is the identity. Reductions are deterministic: every rank gathers the ranks'
// values and combines them in rank order, so all ranks hold the same bits (MPI_Allreduce does
// not promise that) and a run repeats itself exactly.
#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace talus {

/// The mpirun to start distributed children with (`talus verify --mpi`, the scaling bench):
/// TALUS_MPIEXEC if set, else the one this build found. Throws std::runtime_error if it is
/// missing. Lets OpenMPI run as root (it refuses unless told), as CI does.
std::string mpirun_for_children();

class Communicator {
public:
  /// MPI_Init when the process was started by mpirun (its environment says so); call once from
  /// main before anything else. Finalises MPI at exit.
  static void init_if_launched(int& argc, char**& argv);
  /// The run's ranks: MPI_COMM_WORLD after init_if_launched started MPI, else one rank.
  static const Communicator& world();
  /// This process alone: one rank, whatever the run's size; never touches MPI.
  static const Communicator& self();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool distributed() const { return size_ > 1; }
  bool root() const { return rank_ == 0; }
  /// The ranks that share this rank's machine (and its cores).
  int ranks_on_this_machine() const { return local_size_; }
  MPI_Comm mpi() const { return comm_; }

  /// Every rank's value, in rank order.
  template <class T> std::vector<T> all_gather(const T& value) const {
    static_assert(std::is_trivially_copyable_v<T>);
    std::vector<T> out(static_cast<std::size_t>(size_));
    if (!distributed()) {
      out[0] = value;
      return out;
    }
    const Timed timed(*this);
    MPI_Allgather(&value, sizeof(T), MPI_BYTE, out.data(), sizeof(T), MPI_BYTE, comm_);
    return out;
  }
  /// Every rank's values, concatenated in rank order.
  template <class T> std::vector<T> all_gather_v(std::span<const T> values) const {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto bytes = all_gather_bytes(std::as_bytes(values));
    std::vector<T> out(bytes.size() / sizeof(T));
    std::copy(bytes.begin(), bytes.end(), reinterpret_cast<std::byte*>(out.data()));
    return out;
  }
  /// Element-wise sums over the ranks, added in rank order.
  std::vector<double> sum(std::span<const double> values) const;
  double sum(double value) const { return sum(std::span<const double>(&value, 1))[0]; }
  std::int64_t sum(std::int64_t value) const;
  double min(double value) const;
  double max(double value) const;
  bool any(bool value) const;

  /// The first (lowest-rank) message among the ranks that have one, or none: every rank calls
  /// it at the same point, so one rank's failure stops them all with that rank's message.
  std::optional<std::string> first_message(const std::optional<std::string>& mine) const;
  /// Rank 0's string on every rank.
  std::string broadcast(const std::string& value) const;

  /// Sends `to[r]` to each rank r (an empty one is sent too: every pair agrees on the counts)
  /// and returns what each rank sent here, indexed by sender.
  std::vector<std::vector<std::byte>>
  all_to_all(const std::vector<std::vector<std::byte>>& to) const;
  /// Sends to[k] to peers[k] and returns what each peer sent here, in the same order. Both
  /// sides of a pair must name each other; messages may be empty.
  std::vector<std::vector<double>> exchange(std::span<const int> peers,
                                            const std::vector<std::vector<double>>& to) const;

  void barrier() const;

  /// Seconds this rank has spent in communication (waiting for the others included): the
  /// communication share of a distributed run's time.
  double communication_seconds() const { return seconds_; }

private:
  /// Adds the time of the enclosing scope to communication_seconds().
  class Timed {
  public:
    explicit Timed(const Communicator& c) : c_(c), start_(std::chrono::steady_clock::now()) {}
    ~Timed() {
      c_.seconds_ +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }
    Timed(const Timed&) = delete;
    Timed& operator=(const Timed&) = delete;

  private:
    const Communicator& c_;
    std::chrono::steady_clock::time_point start_;
  };

  std::vector<std::byte> all_gather_bytes(std::span<const std::byte> mine) const;

  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0;
  int size_ = 1;
  int local_size_ = 1;
  mutable double seconds_ = 0;
};

} // namespace talus
