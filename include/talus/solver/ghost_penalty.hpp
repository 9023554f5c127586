#pragma once
// Ghost-penalty stabilisation of the implicit grid solve (Burman 2010; for the material point
// method Coombs 2023, "Ghost stabilisation of the material point method for stable
// quasi-static and dynamic analysis of large deformation problems", IJNME).
//
// Why: a grid node whose support holds only a sliver of material (a point that barely reaches
// it) gets a tiny stiffness, and the geometric (initial-stress) stiffness of a compressed point
// can make it negative: the tangent is near singular or indefinite, and a large-deflection
// beam that sweeps across many cells stops with "not positive definite". Dropping such nodes
// stiffens the body badly. The ghost penalty instead ties the displacement of a boundary cell
// to its neighbour's by penalising the jump of the normal derivative across their common face,
//     G(u, v) = gamma E h sum_faces int_face [[du/dn]] . [[dv/dn]] dGamma,
// which vanishes for every linear displacement field (so rigid motion and homogeneous strain
// are untouched, and the penalty is consistent to the order of the Q1 grid field) and gives
// every node of a stabilised face a stiffness of order gamma E however little material it sees.
//
// Which faces: those between two active cells (all 2^Dim nodes carry mass) where at least one
// of the two lies in the boundary band, i.e. has an inactive cell of the grid among its
// 3^Dim - 1 neighbours; a cell beyond a roller face of the grid (a symmetry plane) counts as
// the mirror image of the one inside, not as empty. This is a topological test, independent of how
// much a cell is compressed or stretched (a volume-fraction test would also fire inside a
// compressed body).
//
// On a regular grid the face integral is closed form. For a face with normal along axis d,
// the multilinear basis's normal derivative jumps by (1/h) [-1, 2, -1] across the three node
// layers (behind, on, ahead of the face) times the face's tangential hats, whose mass matrix
// is h^(Dim-1) M^(x)(Dim-1), M = [[1/3, 1/6], [1/6, 1/3]]. So the face matrix over its
// 3 * 2^(Dim-1) nodes is
//     G_face = gamma E h^(Dim-2) (d d^T) (x) M^(x)(Dim-1),   d = [-1, 2, -1],
// acting on each displacement component alike: independent of h in 2D, growing with h in 3D.
#include "talus/grid/active_nodes.hpp"

#include <array>
#include <vector>

namespace talus {

template <int Dim> class GhostPenalty {
public:
  static constexpr int kTangentialNodes = 1 << (Dim - 1);
  static constexpr int kFaceNodes = 3 * kTangentialNodes;
  using FaceMatrix = Eigen::Matrix<double, kFaceNodes, kFaceNodes>;

  /// A stabilised face: its nodes, ordered (normal layer 0..2) x (tangential corner, the lower
  /// tangential axis fastest) so that index kTangentialNodes * layer + t matches face_matrix(),
  /// and gamma E h^(Dim-2) there.
  struct Face {
    std::array<Index, kFaceNodes> nodes{};
    double stiffness = 0;
  };

  /// Finds the stabilised faces among the step's active nodes (node numbers index `nodes`).
  /// node_active[n]: node n carries mass this step;
  /// node_modulus[n]: the largest Young's modulus among the points that reach node n;
  /// gamma: the dimensionless penalty factor (0 switches stabilisation off); mirror_faces[f]:
  /// grid face f (kXMin, kXMax, ...) is a symmetry plane (a roller).
  void build(const ActiveNodes<Dim>& nodes, const std::vector<char>& node_active,
             const std::vector<double>& node_modulus, double gamma,
             const std::array<bool, 2 * Dim>& mirror_faces = {});

  /// Axisymmetry: the face integral per radian carries the radius, taken at the face's centre
  /// (the mean x of its on-face nodes); multiplies every face's stiffness by it.
  void weight_by_radius(const ActiveNodes<Dim>& nodes);

  /// Keeps the faces keep(face) accepts, each node n renumbered to renumber(n): a distributed
  /// run finds the faces on a view of the grid wider than its own nodes and keeps those it
  /// assembles.
  template <class Keep, class Renumber> void select(Keep&& keep, Renumber&& renumber) {
    std::erase_if(faces_, [&](const Face& f) { return !keep(f); });
    for (Face& f : faces_)
      for (Index& n : f.nodes)
        n = renumber(n);
  }

  const std::vector<Face>& faces() const { return faces_; }
  /// (d d^T) (x) M^(x)(Dim-1), the face matrix for unit stiffness.
  static const FaceMatrix& face_matrix();
  /// The face's first node on the face itself (layer 1, corner 0): in a run split into shares,
  /// the share owning it assembles the face.
  static Index anchor(const Face& face) { return face.nodes[kTangentialNodes]; }

private:
  std::vector<Face> faces_;
  std::vector<Index> active_cells_; ///< flat index of every cell whose corners carry mass
  std::vector<char> cell_in_band_;  ///< per active cell: it borders an empty cell
};

} // namespace talus
