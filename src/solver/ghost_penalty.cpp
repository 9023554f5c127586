#include "talus/solver/ghost_penalty.hpp"

#include <algorithm>

namespace talus {

template <int Dim> const typename GhostPenalty<Dim>::FaceMatrix& GhostPenalty<Dim>::face_matrix() {
  static const FaceMatrix matrix = [] {
    const Eigen::Vector3d d(-1.0, 2.0, -1.0);
    Eigen::Matrix2d M;
    M << 1.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0, 1.0 / 3.0;
    // The tangential mass matrix M (x) ... (x) M, Dim - 1 factors.
    Eigen::Matrix<double, kTangentialNodes, kTangentialNodes> T;
    for (int t = 0; t < kTangentialNodes; ++t)
      for (int u = 0; u < kTangentialNodes; ++u) {
        double v = 1.0;
        for (int axis = 0; axis < Dim - 1; ++axis)
          v *= M((t >> axis) & 1, (u >> axis) & 1);
        T(t, u) = v;
      }
    const Eigen::Matrix3d ddT = d * d.transpose();
    FaceMatrix G;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        G.template block<kTangentialNodes, kTangentialNodes>(kTangentialNodes * a,
                                                             kTangentialNodes * b) = ddT(a, b) * T;
    return G;
  }();
  return matrix;
}

template <int Dim>
void GhostPenalty<Dim>::build(const ActiveNodes<Dim>& nodes, const std::vector<char>& node_active,
                              const std::vector<double>& node_modulus, double gamma,
                              const std::array<bool, 2 * Dim>& mirror_faces) {
  faces_.clear();
  if (gamma <= 0.0)
    return;
  const Grid<Dim>& grid = nodes.grid();
  // Cells are indexed by their lowest node in physical lattice coordinates shifted by the ghost
  // layer, from the ghost layer (0) to the last physical cell: nodes(d) - 1 of them along d.
  // Only the cells whose corners all carry mass are listed, ascending in their flat index (the
  // order of their lowest nodes), so nothing is stored for the empty part of the grid.
  using Cell = std::array<Index, Dim>;
  Cell cells{};
  for (int d = 0; d < Dim; ++d)
    cells[d] = grid.nodes(d) - 1;
  auto flat = [&](const Cell& c) {
    Index id = 0;
    for (int d = Dim - 1; d >= 0; --d)
      id = id * cells[d] + c[d];
    return id;
  };
  // The node number at the cell c's corner shifted by `offset` (one lattice step per set bit,
  // axis 0 the lowest bit), -1 if it carries no state.
  auto node = [&](Cell c, unsigned offset) {
    for (int d = 0; d < Dim; ++d)
      c[d] += static_cast<Index>((offset >> d) & 1u) - Grid<Dim>::kGhost;
    return nodes.find(c);
  };
  auto is_active = [&](Index n) { return n >= 0 && node_active[static_cast<std::size_t>(n)]; };
  active_cells_.clear();
  std::vector<Cell> cell_of;
  for (Index n = 0; n < nodes.size(); ++n) {
    Cell c = nodes.ijk(n);
    bool inside = true;
    for (int d = 0; d < Dim; ++d) {
      c[d] += Grid<Dim>::kGhost;
      inside = inside && c[d] < cells[d];
    }
    bool all = inside;
    for (unsigned corner = 0; corner < (1u << Dim) && all; ++corner)
      all = is_active(node(c, corner));
    if (all) {
      active_cells_.push_back(flat(c));
      cell_of.push_back(c);
    }
  }
  // The position of cell c among the active cells, -1 if it is not one.
  auto find_cell = [&](const Cell& c) -> Index {
    for (int d = 0; d < Dim; ++d)
      if (c[d] < 0 || c[d] >= cells[d])
        return -1;
    const Index id = flat(c);
    const auto it = std::lower_bound(active_cells_.begin(), active_cells_.end(), id);
    return it != active_cells_.end() && *it == id ? it - active_cells_.begin() : -1;
  };
  // A cell beyond a mirror face (a roller: a symmetry plane) stands for the mirror image of
  // the cell inside, not for empty space: the body does not end there. Counting it as empty
  // would put every cell of a slab between two z rollers into the band, and the slab would
  // not give the plane-strain answer.
  auto beyond_mirror = [&](const Cell& c) {
    bool outside = false;
    for (int d = 0; d < Dim; ++d) {
      const bool below = c[d] < Grid<Dim>::kGhost;
      const bool above = c[d] >= cells[d] - Grid<Dim>::kGhost;
      if ((below && !mirror_faces[static_cast<std::size_t>(2 * d)]) ||
          (above && !mirror_faces[static_cast<std::size_t>(2 * d + 1)]))
        return false;
      outside = outside || below || above;
    }
    return outside;
  };
  cell_in_band_.assign(active_cells_.size(), 0);
  int neighbours = 1; // 3^Dim offsets in {-1, 0, 1}^Dim
  for (int d = 0; d < Dim; ++d)
    neighbours *= 3;
  for (std::size_t k = 0; k < active_cells_.size(); ++k) {
    bool band = false;
    for (int j = 0; j < neighbours && !band; ++j) {
      Cell n = cell_of[k];
      for (int d = 0, rest = j; d < Dim; ++d, rest /= 3)
        n[d] += rest % 3 - 1;
      band = find_cell(n) < 0 && !beyond_mirror(n);
    }
    cell_in_band_[k] = band;
  }

  const double h_power = Dim == 3 ? grid.cell_size() : 1.0; // h^(Dim - 2)
  for (std::size_t k = 0; k < active_cells_.size(); ++k) {
    const Cell& c = cell_of[k];
    for (int normal = 0; normal < Dim; ++normal) {
      Cell ahead = c;
      ++ahead[normal];
      const Index a = find_cell(ahead);
      if (a < 0 || !(cell_in_band_[k] || cell_in_band_[static_cast<std::size_t>(a)]))
        continue;
      // Layers c, c + e_normal, c + 2 e_normal along the normal; the corners of the face along
      // the other axes, the lowest of them fastest.
      Face face;
      for (int layer = 0; layer < 3; ++layer)
        for (unsigned t = 0; t < static_cast<unsigned>(kTangentialNodes); ++t) {
          unsigned offset = 0;
          for (int axis = 0, bit = 0; axis < Dim; ++axis)
            if (axis != normal)
              offset |= ((t >> bit++) & 1u) << axis;
          Cell base = c;
          base[normal] += layer;
          face.nodes[static_cast<std::size_t>(kTangentialNodes * layer + static_cast<int>(t))] =
              node(base, offset);
        }
      double modulus = 0;
      for (const Index n : face.nodes)
        modulus = std::max(modulus, node_modulus[static_cast<std::size_t>(n)]);
      face.stiffness = gamma * modulus * h_power;
      faces_.push_back(face);
    }
  }
}

template <int Dim> void GhostPenalty<Dim>::weight_by_radius(const ActiveNodes<Dim>& nodes) {
  for (Face& face : faces_) {
    double r = 0;
    for (int t = 0; t < kTangentialNodes; ++t)
      r += nodes.position(face.nodes[static_cast<std::size_t>(kTangentialNodes + t)])[0];
    face.stiffness *= r / kTangentialNodes;
  }
}

template class GhostPenalty<2>;
template class GhostPenalty<3>;

} // namespace talus
