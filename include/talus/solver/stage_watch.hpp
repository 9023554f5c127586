#pragma once
// The ends of a stage (StageSpec) other than its end time and failure: the body has come to
// rest (`at_rest`), or the stage has used up its wall-clock allowance (`wall_time_limit`).
//
// Rest is judged by the kinetic energy of the points' motion over each step,
//   E_motion = sum_p 1/2 m_p |x_p^{n+1} - x_p^n|^2 / dt^2,
// not by the particle velocities: FLIP carries velocity noise that maps to nothing on the grid,
// moves no material and never decays, so a stopped slide could keep its particle kinetic energy
// forever. The stage is at rest once E_motion has stayed at or below `kinetic_energy_ratio`
// times its largest value in the stage for `duration` seconds of the stage's time.
#include "talus/core/particles.hpp"
#include "talus/parallel/communicator.hpp"
#include "talus/spec/case_spec.hpp"

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace talus {

class StageWatch {
public:
  /// `ranks`: the run's, which judge rest and time together.
  explicit StageWatch(const StageSpec& stage, const Communicator& ranks = Communicator::self());

  /// Before each step (attempt): remembers the positions, if the stage watches for rest.
  template <int Dim> void before_step(const Particles<Dim>& P);

  /// After each completed step of length dt ending at the stage time t, before any point is
  /// split: whether the stage ends now; reason() then says why.
  template <int Dim> bool ends_after_step(const Particles<Dim>& P, double t, double dt);

  const std::string& reason() const { return reason_; }
  /// The stage stopped on its wall-time limit (the run stops too).
  bool out_of_time() const { return out_of_time_; }

  /// What the watch has seen of the stage so far (a checkpoint keeps it). The wall-time
  /// allowance is not part of it: a resumed stage has its full allowance again, as a job
  /// resumed on a cluster has a new allocation.
  struct Memory {
    double peak_kinetic = 0;
    std::optional<double> quiet_since{};
  };
  Memory memory() const { return {peak_kinetic_, quiet_since_}; }
  void recall(const Memory& m) {
    peak_kinetic_ = m.peak_kinetic;
    quiet_since_ = m.quiet_since;
  }

private:
  const StageSpec& stage_;
  const Communicator* ranks_; ///< never null
  std::chrono::steady_clock::time_point started_;
  double peak_kinetic_ = 0;
  std::optional<double> quiet_since_{};
  std::vector<Vec3> x_before_{}; ///< z = 0 in 2D
  std::string reason_{};
  bool out_of_time_ = false;
};

} // namespace talus
