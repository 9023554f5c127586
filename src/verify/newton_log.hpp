#pragma once
// What the verification cases read from a run's newton.log: the iterations of its converged load
// steps and the observed order of Newton's convergence.
#include <filesystem>
#include <vector>

namespace talus::verify_cases {

/// Newton iterations of the converged load steps up to `last_step`.
std::vector<int> newton_iterations(const std::filesystem::path& dir, double last_step);

/// The smallest log-ratio log(r_k+1) / log(r_k) over the load steps of the log file, counting
/// only iterates with r_k below 1e-2 (where the quadratic regime has started) and r_k+1 above
/// `floor` (where round-off has not yet taken over).
double worst_newton_order(const std::filesystem::path& log, double floor = 1e-9);

} // namespace talus::verify_cases
