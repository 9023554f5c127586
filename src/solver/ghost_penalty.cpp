#include "talus/solver/ghost_penalty.hpp"

#include <algorithm>

namespace talus {

const GhostPenalty::FaceMatrix& GhostPenalty::face_matrix() {
  static const FaceMatrix matrix = [] {
    const Eigen::Vector3d d(-1.0, 2.0, -1.0);
    Eigen::Matrix2d M;
    M << 1.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0, 1.0 / 3.0;
    const Eigen::Matrix3d ddT = d * d.transpose();
    FaceMatrix G;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        G.block<2, 2>(2 * a, 2 * b) = ddT(a, b) * M;
    return G;
  }();
  return matrix;
}

void GhostPenalty::build(const Grid<2>& grid, const std::vector<char>& node_active,
                         const std::vector<double>& node_modulus, double gamma) {
  faces_.clear();
  if (gamma <= 0.0)
    return;
  // Cells are indexed by their lower-left node in physical lattice coordinates, from the ghost
  // layer (-1) to the last physical cell: cx = nodes(0) - 1 of them along x.
  const Index cx = grid.nodes(0) - 1, cy = grid.nodes(1) - 1;
  const Index g = Grid<2>::kGhost;
  auto node = [&](Index i, Index j) { return grid.node_id({i - g, j - g}); };
  auto cell = [&](Index i, Index j) { return static_cast<std::size_t>(j * cx + i); };
  cell_active_.assign(static_cast<std::size_t>(cx * cy), 0);
  for (Index j = 0; j < cy; ++j)
    for (Index i = 0; i < cx; ++i)
      cell_active_[cell(i, j)] = node_active[static_cast<std::size_t>(node(i, j))] &&
                                 node_active[static_cast<std::size_t>(node(i + 1, j))] &&
                                 node_active[static_cast<std::size_t>(node(i, j + 1))] &&
                                 node_active[static_cast<std::size_t>(node(i + 1, j + 1))];
  auto active = [&](Index i, Index j) {
    return i >= 0 && j >= 0 && i < cx && j < cy && cell_active_[cell(i, j)];
  };
  cell_in_band_.assign(cell_active_.size(), 0);
  for (Index j = 0; j < cy; ++j)
    for (Index i = 0; i < cx; ++i) {
      if (!active(i, j))
        continue;
      bool band = false;
      for (Index dj = -1; dj <= 1 && !band; ++dj)
        for (Index di = -1; di <= 1 && !band; ++di)
          band = !active(i + di, j + dj);
      cell_in_band_[cell(i, j)] = band;
    }

  auto add_face = [&](const std::array<Index, kFaceNodes>& nodes) {
    double modulus = 0;
    for (const Index n : nodes)
      modulus = std::max(modulus, node_modulus[static_cast<std::size_t>(n)]);
    faces_.push_back({nodes, gamma * modulus});
  };
  for (Index j = 0; j < cy; ++j)
    for (Index i = 0; i < cx; ++i) {
      if (!active(i, j))
        continue;
      const bool band = cell_in_band_[cell(i, j)];
      // The face to the right: node columns i, i+1, i+2 along the normal, rows j, j+1 along it.
      if (active(i + 1, j) && (band || cell_in_band_[cell(i + 1, j)]))
        add_face({node(i, j), node(i, j + 1), node(i + 1, j), node(i + 1, j + 1), node(i + 2, j),
                  node(i + 2, j + 1)});
      // The face above: node rows j, j+1, j+2 along the normal, columns i, i+1 along it.
      if (active(i, j + 1) && (band || cell_in_band_[cell(i, j + 1)]))
        add_face({node(i, j), node(i + 1, j), node(i, j + 1), node(i + 1, j + 1), node(i, j + 2),
                  node(i + 1, j + 2)});
    }
}

} // namespace talus
