#include "talus/parallel/partition_boxes.hpp"

#include "../../linalg/trilinos/trilinos_solver.hpp"

#include <Teuchos_DefaultMpiComm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Zoltan2_BasicVectorAdapter.hpp>
#include <Zoltan2_PartitioningProblem.hpp>

#include <limits>
#include <stdexcept>

namespace talus {

std::vector<PartBox> partition_boxes(int dim, const std::vector<double>& coordinates,
                                     const std::vector<double>& weights, MPI_Comm comm) {
  using Types = Zoltan2::BasicUserTypes<double, int, long long>;
  using Adapter = Zoltan2::BasicVectorAdapter<Types>;
  detail::ensure_tpetra_initialized(); // Zoltan2 works in Kokkos views
  int ranks = 1, rank = 0;
  MPI_Comm_size(comm, &ranks);
  MPI_Comm_rank(comm, &rank);
  const auto n = weights.size();
  if (coordinates.size() != n * static_cast<std::size_t>(dim))
    throw std::logic_error("partition_boxes: coordinates and weights disagree");

  // Zoltan2 wants distinct global ids: this rank's offset plus the local index.
  long long offset = 0, count = static_cast<long long>(n);
  MPI_Exscan(&count, &offset, 1, MPI_LONG_LONG, MPI_SUM, comm);
  if (rank == 0)
    offset = 0;
  std::vector<long long> ids(n);
  for (std::size_t i = 0; i < n; ++i)
    ids[i] = offset + static_cast<long long>(i);
  std::vector<std::vector<double>> axis(3);
  for (int d = 0; d < dim; ++d) {
    axis[static_cast<std::size_t>(d)].resize(n);
    for (std::size_t i = 0; i < n; ++i)
      axis[static_cast<std::size_t>(d)][i] = coordinates[i * static_cast<std::size_t>(dim) + d];
  }
  // An empty rank still hands Zoltan2 valid (non-null) arrays.
  static const double none = 0.0;
  auto data = [&](int d) { return d < dim ? (n ? axis[d].data() : &none) : nullptr; };
  Adapter adapter(static_cast<int>(n), ids.data(), data(0), data(1), data(2), 1, 1, 1, true,
                  n ? weights.data() : &none, 1);

  Teuchos::ParameterList params("talus partition");
  params.set("algorithm", "multijagged");
  params.set("num_global_parts", ranks);
  params.set("mj_keep_part_boxes", true);
  params.set("imbalance_tolerance", 1.05);
  params.set("error_check_level", "no_assertions");
  params.set("timer_output_stream", "null");
  const Teuchos::RCP<const Teuchos::Comm<int>> tcomm =
      Teuchos::rcp(new Teuchos::MpiComm<int>(comm));
  Zoltan2::PartitioningProblem<Adapter> problem(&adapter, &params, tcomm);
  problem.solve();

  std::vector<PartBox> boxes(static_cast<std::size_t>(ranks));
  const auto& found = problem.getSolution().getPartBoxesView();
  for (const auto& box : found) {
    PartBox& b = boxes.at(static_cast<std::size_t>(box.getpId()));
    for (int d = 0; d < 3; ++d) {
      const bool real = d < dim;
      // Zoltan2 marks an unbounded face with its largest scalar.
      const double lo = real ? box.getlmins()[d] : -1.0, hi = real ? box.getlmaxs()[d] : 1.0;
      b.lower[static_cast<std::size_t>(d)] = lo <= -0.5 * std::numeric_limits<double>::max()
                                                 ? -std::numeric_limits<double>::infinity()
                                                 : lo;
      b.upper[static_cast<std::size_t>(d)] = hi >= 0.5 * std::numeric_limits<double>::max()
                                                 ? std::numeric_limits<double>::infinity()
                                                 : hi;
    }
  }
  return boxes;
}

} // namespace talus
