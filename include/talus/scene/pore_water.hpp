#pragma once
// The water that acts on the points now. Within a stage the water table moves from the one
// before the stage (none while the first stage's weight grows from zero) to the stage's own,
// with the stage's progress f: u = (1 - f) u_from + f u_to, and likewise its gradient. A
// point's material gives its effective stress sigma'; the point holds the total stress
// sigma' - u I. The grid's equilibrium is written on the effective stress, with -grad u as a
// body force: by the divergence theorem this is the total stress in balance with the free
// water's pressure u on every face of the body below the surface (a reservoir, ponding), and
// the points carry that face pressure as it moves, without a surface to find
// (docs/case-format.md, water).
#include "talus/scene/water_table.hpp"

#include <optional>

namespace talus {

class PoreWater {
public:
  PoreWater() = default;
  /// From `from` to `to` (either may be none: dry).
  PoreWater(std::optional<WaterTable> from, std::optional<WaterTable> to)
      : from_(std::move(from)), to_(std::move(to)) {}

  /// The water of a case at rest: its own water table, whole.
  static PoreWater of(const CaseSpec& spec) {
    const auto table = WaterTable::of(spec);
    return {table, table};
  }

  /// Whether any water acts (a dry case or stage has none).
  bool any() const { return from_ || to_; }

  /// The stage's progress f in [0, 1]: the share of the move made (at a step's end), and at
  /// the step's start `start`.
  void set_progress(double f, double start) {
    progress_ = f;
    start_ = start;
  }
  void set_progress(double f) { set_progress(f, f); }
  double progress() const { return progress_; }

  /// Consolidation: no flow in this stage (StageSpec::undrained); the table still gives u and
  /// the faces' free water.
  void set_undrained(bool undrained) { undrained_ = undrained; }
  bool undrained() const { return undrained_; }

  /// u at x, Pa (compression positive).
  template <int Dim> double pore_pressure(const Vec<Dim>& x) const {
    return blend([&](const WaterTable& w) { return w.pore_pressure<Dim>(x); }, 0.0);
  }
  /// u at x at the step's start.
  template <int Dim> double pore_pressure_at_start(const Vec<Dim>& x) const {
    return blend([&](const WaterTable& w) { return w.pore_pressure<Dim>(x); }, 0.0, start_);
  }
  /// grad u at x, Pa/m.
  template <int Dim> Vec<Dim> pressure_gradient(const Vec<Dim>& x) const {
    return blend([&](const WaterTable& w) { return w.pressure_gradient<Dim>(x); },
                 Vec<Dim>::Zero().eval());
  }

private:
  template <class F, class T> T blend(F&& of, T none) const { return blend(of, none, progress_); }
  template <class F, class T> T blend(F&& of, T none, double f) const {
    T v = none;
    if (from_ && f < 1.0)
      v = (1.0 - f) * of(*from_);
    if (to_ && f > 0.0)
      v = v + f * of(*to_);
    return v;
  }

  std::optional<WaterTable> from_, to_;
  double progress_ = 1.0, start_ = 1.0;
  bool undrained_ = false;
};

} // namespace talus
