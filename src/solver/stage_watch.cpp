#include "talus/solver/stage_watch.hpp"

#include <algorithm>
#include <fmt/format.h>

namespace talus {

StageWatch::StageWatch(const StageSpec& stage, const Communicator& ranks)
    : stage_(stage), ranks_(&ranks), started_(std::chrono::steady_clock::now()) {}

template <int Dim> void StageWatch::before_step(const Particles<Dim>& P) {
  if (!stage_.at_rest)
    return;
  x_before_.resize(P.x.size());
  for (std::size_t p = 0; p < P.x.size(); ++p)
    x_before_[p] = padded<Dim>(P.x[p]);
}

template <int Dim> bool StageWatch::ends_after_step(const Particles<Dim>& P, double t, double dt) {
  if (stage_.at_rest) {
    double kinetic_energy = 0;
    for (std::size_t p = 0; p < x_before_.size(); ++p)
      kinetic_energy +=
          0.5 * P.mass[p] * (padded<Dim>(P.x[p]) - x_before_[p]).squaredNorm() / (dt * dt);
    kinetic_energy = ranks_->sum(kinetic_energy);
    peak_kinetic_ = std::max(peak_kinetic_, kinetic_energy);
    if (kinetic_energy <= stage_.at_rest->kinetic_energy_ratio * peak_kinetic_) {
      if (!quiet_since_)
        quiet_since_ = t;
      if (t - *quiet_since_ >= stage_.at_rest->duration * (1.0 - 1e-12)) {
        reason_ = fmt::format("at rest: kinetic energy at most {:g} of its peak {:.4g} J/m since "
                              "stage time {:g} s (held {:g} s)",
                              stage_.at_rest->kinetic_energy_ratio, peak_kinetic_, *quiet_since_,
                              t - *quiet_since_);
        return true;
      }
    } else {
      quiet_since_.reset();
    }
  }
  if (stage_.wall_time_limit) {
    double used =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    used = ranks_->max(used); // the slowest rank's clock: all ranks stop at the same step
    if (used > *stage_.wall_time_limit) {
      reason_ = fmt::format("wall-time limit: {:.1f} s used of the stage's {:g} s at stage time "
                            "{:g} s",
                            used, *stage_.wall_time_limit, t);
      out_of_time_ = true;
      return true;
    }
  }
  return false;
}

template void StageWatch::before_step<2>(const Particles<2>&);
template void StageWatch::before_step<3>(const Particles<3>&);
template bool StageWatch::ends_after_step<2>(const Particles<2>&, double, double);
template bool StageWatch::ends_after_step<3>(const Particles<3>&, double, double);

} // namespace talus
