#pragma once
// What the verification cases read from a run's newton.log: the iterations of its converged load
// steps and the observed order of Newton's convergence, and the rows that check them. A log that
// is missing or measures nothing fails its row: it never passes it, nor drops it.
#include "talus/verify/verification.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace talus::verify_cases {

/// Newton iterations of the converged load steps up to `last_step`.
std::vector<int> newton_iterations(const std::filesystem::path& dir, double last_step);

/// The smallest log-ratio log(r_k+1) / log(r_k) over the load steps of the log file, counting
/// only iterates with r_k below 1e-2 (where the quadratic regime has started) and r_k+1 above
/// `floor` (where round-off has not yet taken over); none without such a pair or without a log.
std::optional<double> worst_newton_order(const std::filesystem::path& log, double floor = 1e-9);

/// "The worst observed order of the log is at least `lower`"; fails when nothing was measured.
Check newton_order_check(std::string quantity, const std::filesystem::path& log, double lower,
                         std::string note);

/// "At most `upper` Newton iterations per converged step" at the given quantile of `iterations`
/// (0.5: the median, 1: the largest); fails when there is no converged step.
Check newton_iterations_check(std::string quantity, std::vector<int> iterations, double quantile,
                              double upper, std::string note);

} // namespace talus::verify_cases
