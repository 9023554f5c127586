#include "talus/parallel/communicator.hpp"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <unistd.h>

namespace talus {

namespace {

bool launched_by_mpirun() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(var) != nullptr)
      return true;
  return false;
}

Communicator& the_world() {
  static Communicator world;
  return world;
}

int count_of(std::size_t n) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::runtime_error("an MPI message above 2 GiB");
  return static_cast<int>(n);
}

} // namespace

std::string mpirun_for_children() {
  const char* from_env = std::getenv("TALUS_MPIEXEC");
  std::string mpirun = from_env ? from_env : TALUS_MPIEXEC;
  if (::access(mpirun.c_str(), X_OK) != 0)
    throw std::runtime_error(mpirun + " not found (set TALUS_MPIEXEC)");
  if (::geteuid() == 0) {
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  }
  return mpirun;
}

void Communicator::init_if_launched(int& argc, char**& argv) {
  if (!launched_by_mpirun())
    return;
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) {
    int provided = 0;
    // Only the main thread calls MPI; OpenMP threads work between the calls.
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    std::atexit([] {
      int finalized = 0;
      MPI_Finalized(&finalized);
      if (!finalized)
        MPI_Finalize();
    });
  }
  Communicator& w = the_world();
  w.comm_ = MPI_COMM_WORLD;
  MPI_Comm_rank(MPI_COMM_WORLD, &w.rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &w.size_);
  MPI_Comm local;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, w.rank_, MPI_INFO_NULL, &local);
  MPI_Comm_size(local, &w.local_size_);
  MPI_Comm_free(&local);
}

const Communicator& Communicator::world() {
  return the_world();
}

const Communicator& Communicator::self() {
  static const Communicator alone;
  return alone;
}

std::vector<std::byte> Communicator::all_gather_bytes(std::span<const std::byte> mine) const {
  if (!distributed())
    return {mine.begin(), mine.end()};
  const std::vector<int> counts = all_gather(count_of(mine.size()));
  std::vector<int> offsets(counts.size(), 0);
  for (std::size_t r = 1; r < counts.size(); ++r)
    offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<std::byte> out(static_cast<std::size_t>(offsets.back() + counts.back()));
  const Timed timed(*this);
  MPI_Allgatherv(mine.data(), count_of(mine.size()), MPI_BYTE, out.data(), counts.data(),
                 offsets.data(), MPI_BYTE, comm_);
  return out;
}

std::vector<double> Communicator::sum(std::span<const double> values) const {
  std::vector<double> total(values.begin(), values.end());
  if (!distributed())
    return total;
  const std::vector<double> all = all_gather_v(values);
  std::fill(total.begin(), total.end(), 0.0);
  for (int r = 0; r < size_; ++r)
    for (std::size_t i = 0; i < values.size(); ++i)
      total[i] += all[static_cast<std::size_t>(r) * values.size() + i];
  return total;
}

std::int64_t Communicator::sum(std::int64_t value) const {
  std::int64_t total = 0;
  for (const std::int64_t v : all_gather(value))
    total += v;
  return total;
}

double Communicator::min(double value) const {
  const auto all = all_gather(value);
  return *std::min_element(all.begin(), all.end());
}

double Communicator::max(double value) const {
  const auto all = all_gather(value);
  return *std::max_element(all.begin(), all.end());
}

bool Communicator::any(bool value) const {
  const auto all = all_gather(static_cast<char>(value));
  return std::any_of(all.begin(), all.end(), [](char v) { return v != 0; });
}

std::optional<std::string>
Communicator::first_message(const std::optional<std::string>& mine) const {
  if (!distributed())
    return mine;
  const std::vector<int> has = all_gather(mine ? 1 : 0);
  const auto first = std::find(has.begin(), has.end(), 1);
  if (first == has.end())
    return std::nullopt;
  const int from = static_cast<int>(first - has.begin());
  const Timed timed(*this);
  int length = rank_ == from ? count_of(mine->size()) : 0;
  MPI_Bcast(&length, 1, MPI_INT, from, comm_);
  std::string text(static_cast<std::size_t>(length), '\0');
  if (rank_ == from)
    text = *mine;
  MPI_Bcast(text.data(), length, MPI_CHAR, from, comm_);
  return text;
}

std::string Communicator::broadcast(const std::string& value) const {
  if (!distributed())
    return value;
  const Timed timed(*this);
  int length = count_of(value.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, comm_);
  std::string text = root() ? value : std::string(static_cast<std::size_t>(length), '\0');
  MPI_Bcast(text.data(), length, MPI_CHAR, 0, comm_);
  return text;
}

std::vector<std::vector<std::byte>>
Communicator::all_to_all(const std::vector<std::vector<std::byte>>& to) const {
  if (!distributed())
    return {to.at(0)};
  const auto n = static_cast<std::size_t>(size_);
  std::vector<int> send_counts(n), recv_counts(n), send_offsets(n, 0), recv_offsets(n, 0);
  for (std::size_t r = 0; r < n; ++r)
    send_counts[r] = count_of(to[r].size());
  const Timed timed(*this);
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm_);
  std::vector<std::byte> send;
  for (std::size_t r = 0; r < n; ++r) {
    send_offsets[r] = count_of(send.size());
    send.insert(send.end(), to[r].begin(), to[r].end());
  }
  for (std::size_t r = 1; r < n; ++r)
    recv_offsets[r] = recv_offsets[r - 1] + recv_counts[r - 1];
  std::vector<std::byte> received(
      static_cast<std::size_t>(recv_offsets.back() + recv_counts.back()));
  MPI_Alltoallv(send.data(), send_counts.data(), send_offsets.data(), MPI_BYTE, received.data(),
                recv_counts.data(), recv_offsets.data(), MPI_BYTE, comm_);
  std::vector<std::vector<std::byte>> out(n);
  for (std::size_t r = 0; r < n; ++r)
    out[r].assign(received.begin() + recv_offsets[r],
                  received.begin() + recv_offsets[r] + recv_counts[r]);
  return out;
}

std::vector<std::vector<double>>
Communicator::exchange(std::span<const int> peers,
                       const std::vector<std::vector<double>>& to) const {
  constexpr int kCountTag = 7101, kDataTag = 7102;
  const std::size_t n = peers.size();
  std::vector<std::vector<double>> from(n);
  if (n == 0)
    return from;
  std::vector<int> send_counts(n), recv_counts(n);
  std::vector<MPI_Request> requests(2 * n);
  const Timed timed(*this);
  for (std::size_t k = 0; k < n; ++k) {
    send_counts[k] = count_of(to[k].size());
    MPI_Irecv(&recv_counts[k], 1, MPI_INT, peers[k], kCountTag, comm_, &requests[k]);
    MPI_Isend(&send_counts[k], 1, MPI_INT, peers[k], kCountTag, comm_, &requests[n + k]);
  }
  MPI_Waitall(count_of(2 * n), requests.data(), MPI_STATUSES_IGNORE);
  for (std::size_t k = 0; k < n; ++k) {
    from[k].resize(static_cast<std::size_t>(recv_counts[k]));
    MPI_Irecv(from[k].data(), recv_counts[k], MPI_DOUBLE, peers[k], kDataTag, comm_, &requests[k]);
    MPI_Isend(to[k].data(), send_counts[k], MPI_DOUBLE, peers[k], kDataTag, comm_,
              &requests[n + k]);
  }
  MPI_Waitall(count_of(2 * n), requests.data(), MPI_STATUSES_IGNORE);
  return from;
}

void Communicator::barrier() const {
  if (distributed()) {
    const Timed timed(*this);
    MPI_Barrier(comm_);
  }
}

} // namespace talus
