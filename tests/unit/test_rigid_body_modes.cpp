// The rigid-body modes handed to MueLu (include/talus/solver/rigid_body_modes.hpp) are the null
// space of the elastic tangent of a free, stress-free body: K m = 0 for every mode, in plane
// strain, 3D and axisymmetry (where only the axial translation is rigid). A wrong sign or
// component in a rotation leaves K m of the order of K's entries times the body's size.
#include "../../src/solver/implicit_share_assembly.hpp"
#include "talus/grid/particle_grid_map.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/linalg/dof_map.hpp"
#include "talus/scene/scene.hpp"
#include "talus/shape/shape_functions.hpp"
#include "talus/solver/implicit_solver.hpp"
#include "talus/solver/rigid_body_modes.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace {

using namespace talus;

/// A free Hencky block, no loads, no boundary conditions: its tangent at du = 0 is the elastic
/// stiffness, singular exactly on the rigid motions.
std::string free_block(int dimension, const std::string& geometry) {
  const bool three = dimension == 3;
  return std::string("name: modes\nanalysis: implicit_quasistatic\n") +
         (three ? "dimension: 3\n" : "") + geometry +
         (three ? "grid: {origin: [0, 0, 0], extent: [1.5, 1.25, 1], cell_size: 0.25}\n"
                : "grid: {origin: [0, 0], extent: [2, 1.5], cell_size: 0.25}\n") +
         "materials:\n  - {name: m, model: hencky, density: 1000, youngs_modulus: 1.0e6, "
         "poisson_ratio: 0.3}\nbodies:\n  - {name: b, material: m, " +
         (three ? "shape: box, min: [0.25, 0.25, 0.25], max: [1, 0.75, 0.75]"
                : "shape: rectangle, min: [0, 0.25], max: [1.25, 1]") +
         ", particles_per_cell: 2}\ngravity: " + (three ? "[0, 0, 0]" : "[0, 0]") +
         "\ntime: {end_time: 1, dt: 1}\nsolver: {ghost_penalty: 0}\n";
}

/// max |K m| / (max |K| max |m|) over the modes, and the number of modes.
template <int Dim, bool Axisymmetric>
std::pair<double, Index> worst_residual(const std::string& t) {
  Scene<Dim> scene = build_scene<Dim>(read_case_text(t, "modes"));
  auto owned = make_implicit_solver<Dim>(scene);
  ImplicitShareAssembly* solver = &share_assembly(*owned);
  solver->prepare(1.0, 1.0, 1.0);
  const ParticleShare whole{0, 0, scene.particles.size()};
  const std::vector<ParticleShare> shares{whole};
  const DofMap map = solver->dof_map(whole, solver->node_owners(shares));
  Eigen::VectorXd r;
  SparseMatrix K;
  EXPECT_TRUE(
      solver->assemble_share(whole, map, Eigen::VectorXd::Zero(map.overlap_count()), &r, &K));
  // The solver's active nodes, rebuilt the way it builds them (the same map of the same points).
  ParticleGridMap<Dim, GimpShape> nodes_of;
  nodes_of.update(scene.grid, scene.particles);
  const Eigen::MatrixXd modes = rigid_body_modes<Dim, Axisymmetric>(
      nodes_of.nodes(), solver->global_dofs(), solver->unknowns());
  const double scale = Eigen::MatrixXd(K).cwiseAbs().maxCoeff() * modes.cwiseAbs().maxCoeff();
  const double worst = (K * modes).cwiseAbs().maxCoeff() / scale;
  std::printf("%d modes on %lld unknowns: max |K m| / (max |K| max |m|) = %.3g\n",
              static_cast<int>(modes.cols()), static_cast<long long>(modes.rows()), worst);
  return {worst, modes.cols()};
}

// Measured: 1.6e-16 (plane strain, axisymmetry) and 1.3e-15 (3D), round-off of sums of K's
// entries; a wrong mode gives order 0.1 (tried: the rotations' first component with its sign
// flipped, 0.089 in plane strain and 0.12 in 3D; a radial instead of an axial translation in
// axisymmetry, which stretches the hoops, fails too). 1e-12 leaves room for round-off on other
// compilers and larger blocks, far below what a wrong mode gives.
constexpr double kNullTolerance = 1e-12;

TEST(RigidBodyModes, PlaneStrainTangentAnnihilatesThem) {
  const auto [worst, count] = worst_residual<2, false>(free_block(2, ""));
  EXPECT_EQ(count, 3);
  EXPECT_LT(worst, kNullTolerance);
}

TEST(RigidBodyModes, ThreeDimensionalTangentAnnihilatesThem) {
  const auto [worst, count] = worst_residual<3, false>(free_block(3, ""));
  EXPECT_EQ(count, 6);
  EXPECT_LT(worst, kNullTolerance);
}

TEST(RigidBodyModes, AxisymmetricTangentAnnihilatesTheAxialTranslation) {
  const auto [worst, count] = worst_residual<2, true>(free_block(2, "geometry: axisymmetric\n"));
  EXPECT_EQ(count, 1);
  EXPECT_LT(worst, kNullTolerance);
}

} // namespace
