#pragma once
// What an implicit load step holds per active node, as a structure of arrays: the implicit
// step's GridState (grid/grid_state.hpp). One list of the fields (for_each_field) sizes them
// when the step is set up, so a new nodal field (a pore pressure's prescribed value, a body's
// own load) is one more member and one more line in the list. The unknowns themselves are
// numbered by the step's NodeDofs (linalg/node_layout.hpp), not stored here.
#include "talus/core/types.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace talus {

template <int Dim> struct ImplicitNodeFields {
  std::vector<double> mass;         ///< summed over the ranks that share the node
  std::vector<std::int32_t> region; ///< the prescribed box that holds the node, -1 if none
  /// Per component, the face that receives its reaction (FaceConditions::reaction_faces).
  std::vector<std::array<std::int8_t, Dim>> reaction_face;
  std::vector<int> owner;              ///< the rank that owns the node (its lowest holder)
  std::vector<Vec<Dim>> prescribed_du; ///< this step's prescribed increment
  std::vector<Vec<Dim>> load;          ///< the external load (for the reactions)
  /// Consolidation only (empty otherwise): the points' pore pressure at the step's start,
  /// projected (mass-weighted), and on a drained node the increment to its held value.
  std::vector<double> pressure, prescribed_dp;
  std::vector<char> drained; ///< consolidation only: the pore pressure is held here

  /// f(name, array) for every per-node array.
  template <class F> void for_each_field(F&& f) {
    f("mass", mass);
    f("region", region);
    f("reaction_face", reaction_face);
    f("owner", owner);
    f("prescribed_du", prescribed_du);
    f("load", load);
  }

  /// f(name, array) for the consolidation's per-node arrays.
  template <class F> void for_each_pressure_field(F&& f) {
    f("pressure", pressure);
    f("prescribed_dp", prescribed_dp);
    f("drained", drained);
  }

  /// One entry per node of the step; values are left to the step to set.
  void resize(Index nodes, bool pressure_fields) {
    const auto size = [&](const char*, auto& a) { a.resize(static_cast<std::size_t>(nodes)); };
    for_each_field(size);
    if (pressure_fields)
      for_each_pressure_field(size);
  }
};

} // namespace talus
