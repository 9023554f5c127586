// Point migration (parallel/migration.hpp) under mpirun: every rank runs these tests on its
// share of the points. A point that moves to another rank arrives with every array it carries,
// its material history, its tractions and its probe; nothing is lost, duplicated or changed,
// so the mass and momentum summed in the serial order are bitwise those before the move.
#include "talus/io/case_reader.hpp"
#include "talus/scene/migration.hpp"
#include "talus/scene/scene.hpp"

#include <gtest/gtest.h>

#include <map>
#include <numeric>

namespace {

using namespace talus;

const std::string kCases = std::string(TALUS_SOURCE_DIR) + "/cases/";

/// What a point carries, keyed by its global id: every particle array's values and each
/// material's history row, flattened. Gathered on rank 0.
std::map<std::int64_t, std::vector<double>> state_by_id(const Scene<2>& scene) {
  const auto& P = scene.particles;
  const auto n = static_cast<std::size_t>(P.size());
  std::vector<std::vector<double>> history;
  for (const auto& m : scene.materials)
    history.push_back(m->history());
  std::vector<double> mine;
  for (std::size_t p = 0; p < n; ++p) {
    std::vector<double> row;
    P.for_each_field([&](const char*, const auto& a, const auto&) {
      using T = std::decay_t<decltype(a[p])>;
      if constexpr (std::is_arithmetic_v<T>)
        row.push_back(static_cast<double>(a[p]));
      else
        row.insert(row.end(), a[p].data(), a[p].data() + T::SizeAtCompileTime);
    });
    for (const auto& h : history) {
      const std::size_t w = h.size() / n;
      row.insert(row.end(), h.begin() + static_cast<long>(p * w),
                 h.begin() + static_cast<long>((p + 1) * w));
    }
    mine.push_back(static_cast<double>(row.size()));
    mine.insert(mine.end(), row.begin(), row.end());
  }
  const auto& comm = Communicator::world();
  const std::vector<double> all = comm.all_gather_v(std::span<const double>(mine));
  std::map<std::int64_t, std::vector<double>> out;
  for (std::size_t i = 0; i < all.size();) {
    const auto len = static_cast<std::size_t>(all[i]);
    std::vector<double> row(all.begin() + static_cast<long>(i + 1),
                            all.begin() + static_cast<long>(i + 1 + len));
    // global_id is the last particle array (for_each_field order)
    std::int64_t id = -1;
    std::size_t k = 0;
    P.for_each_field([&](const char* name, const auto& a, const auto&) {
      using T = std::decay_t<decltype(a[0])>;
      constexpr std::size_t width = [] {
        if constexpr (std::is_arithmetic_v<T>)
          return std::size_t{1};
        else
          return static_cast<std::size_t>(T::SizeAtCompileTime);
      }();
      if (std::string_view(name) == "global_id")
        id = static_cast<std::int64_t>(row[k]);
      k += width;
    });
    out[id] = std::move(row);
    i += 1 + len;
  }
  return out;
}

/// Sum of a per-point quantity over all ranks in global id order (the serial order).
template <class F> double sum_in_serial_order(const Scene<2>& scene, F&& value) {
  const auto& P = scene.particles;
  std::vector<double> mine;
  for (std::size_t p = 0; p < P.x.size(); ++p) {
    mine.push_back(static_cast<double>(P.global_id[p]));
    mine.push_back(value(p));
  }
  const auto all = Communicator::world().all_gather_v(std::span<const double>(mine));
  std::map<double, double> ordered;
  for (std::size_t i = 0; i < all.size(); i += 2)
    ordered[all[i]] = all[i + 1];
  double total = 0;
  for (const auto& [id, v] : ordered)
    total += v;
  return total;
}

// Plastic discs with a probe each: every point shifted by 0.3 m along x (most cross the cut)
// and migrated.
TEST(Migration, PointsArriveWithEverythingTheyCarry) {
  const auto& comm = Communicator::world();
  ASSERT_TRUE(comm.distributed()) << "run under mpirun -np 2 or more";
  CaseSpec spec = read_case_file(kCases + "colliding_discs_tresca.yaml", {});
  Scene<2> scene = build_scene<2>(spec);
  const Index total = scene.particles.size();
  distribute_scene(scene, comm);
  ASSERT_TRUE(scene.distributed());
  // A history that differs from point to point: each material evaluated at an F of its own.
  auto& P = scene.particles;
  for (std::size_t p = 0; p < P.x.size(); ++p) {
    const double g = static_cast<double>(P.global_id[p]);
    P.F[p](0, 1) = 1e-3 * std::sin(g);
    P.v[p] = Vec2(g, -0.5 * g);
  }
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    scene.materials[m]->update_stress(scene.particles_of_material[m], P.F, P.stress);

  for (auto& x : P.x)
    x.x() += 0.3;
  const auto before = state_by_id(scene);
  const double mass = sum_in_serial_order(scene, [&](std::size_t p) { return P.mass[p]; });
  const double momentum =
      sum_in_serial_order(scene, [&](std::size_t p) { return P.mass[p] * P.v[p].x(); });

  const MigrationCount moved = migrate_points(scene);
  EXPECT_GT(comm.sum(std::int64_t{moved.sent}), 0);
  EXPECT_EQ(comm.sum(std::int64_t{moved.sent}), comm.sum(std::int64_t{moved.received}));
  EXPECT_EQ(comm.sum(std::int64_t{scene.particles.size()}), total);
  for (const auto& x : P.x)
    EXPECT_EQ(scene.decomposition->owner(x), comm.rank());
  EXPECT_TRUE(std::is_sorted(P.global_id.begin(), P.global_id.end()));
  EXPECT_EQ(state_by_id(scene), before) << "a point's state changed on its way";
  EXPECT_EQ(sum_in_serial_order(scene, [&](std::size_t p) { return P.mass[p]; }), mass);
  EXPECT_EQ(sum_in_serial_order(scene, [&](std::size_t p) { return P.mass[p] * P.v[p].x(); }),
            momentum);
  // The material batches list exactly the rank's points.
  Index batched = 0;
  for (const auto& batch : scene.particles_of_material)
    batched += static_cast<Index>(batch.size());
  EXPECT_EQ(batched, scene.particles.size());
  // Each probe lives on exactly one rank, at a point it still names.
  for (std::size_t k = 0; k < scene.probe_particles.size(); ++k)
    EXPECT_EQ(comm.sum(std::int64_t{scene.probe_particles[k] >= 0 ? 1 : 0}), 1) << "probe " << k;
}

// Gathered for a frame, the points are the serial scene's, in its order. One body, whose
// lattice the cuts split row by row: the ranks' shares interleave in the serial order.
TEST(Migration, AGatheredFrameIsTheSerialScene) {
  const auto& comm = Communicator::world();
  CaseSpec spec = read_case_file(kCases + "slope_3d.yaml", {});
  const Scene<3> serial = build_scene<3>(spec);
  Scene<3> scene = build_scene<3>(spec);
  distribute_scene(scene, comm);
  const Particles<3> all = gather_points(scene, nullptr);
  if (!comm.root()) {
    EXPECT_EQ(all.size(), 0);
    return;
  }
  ASSERT_EQ(all.size(), serial.particles.size());
  for (std::size_t p = 0; p < all.x.size(); ++p) {
    ASSERT_EQ(all.global_id[p], static_cast<std::int64_t>(p));
    ASSERT_EQ(all.x[p], serial.particles.x[p]);
    ASSERT_EQ(all.mass[p], serial.particles.mass[p]);
  }
}

} // namespace

int main(int argc, char** argv) {
  talus::Communicator::init_if_launched(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  // One rank's report is enough to read; every rank's result counts in the exit code.
  if (!talus::Communicator::world().root())
    delete ::testing::UnitTest::GetInstance()->listeners().Release(
        ::testing::UnitTest::GetInstance()->listeners().default_result_printer());
  const int failed = RUN_ALL_TESTS();
  return talus::Communicator::world().any(failed != 0) ? 1 : 0;
}
