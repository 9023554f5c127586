#pragma once
// What an explicit step holds on its active nodes, as a structure of arrays: the grid side of
// Particles. One list of the fields (for_each_field) sizes them every step, the halo sums and
// the state guard read its arrays, and a new nodal field (a body's own velocity for contact, a
// pore pressure) is one more member and one more line in the list.
#include "talus/core/types.hpp"

#include <array>
#include <cstdint>

namespace talus {

template <int Dim> struct GridState {
  Array<double> mass;
  Array<Vec<Dim>> momentum;
  Array<Vec<Dim>> force;
  Array<Vec<Dim>> velocity;
  Array<Vec<Dim>> acceleration;
  Array<std::uint8_t> held;                          ///< FaceConditions::held
  Array<std::array<std::int8_t, Dim>> reaction_face; ///< FaceConditions::reaction_faces

  /// f(name, array) for every per-node array.
  template <class F> void for_each_field(F&& f) {
    f("mass", mass);
    f("momentum", momentum);
    f("force", force);
    f("velocity", velocity);
    f("acceleration", acceleration);
    f("held", held);
    f("reaction_face", reaction_face);
  }

  /// One entry per node of the step; values are left to the step to set.
  void resize(Index nodes) {
    for_each_field([&](const char*, auto& a) { a.resize(static_cast<std::size_t>(nodes)); });
  }
};

} // namespace talus
