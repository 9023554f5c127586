// The check builders of the verification suite: each states its acceptance and decides it.
#include "talus/verify/verification.hpp"

#include <cmath>

namespace talus {

namespace {

Check make(std::string quantity, Acceptance acceptance, double measured, std::string note) {
  Check c;
  c.quantity = std::move(quantity);
  c.acceptance = acceptance;
  c.measured = measured;
  c.reference = NAN;
  c.error = NAN;
  c.lower = NAN;
  c.upper = NAN;
  c.note = std::move(note);
  return c;
}

} // namespace

Verdict Check::verdict() const {
  if (acceptance == Acceptance::report)
    return Verdict::report;
  if (known_defect.empty())
    return passed ? Verdict::pass : Verdict::fail;
  return passed ? Verdict::unexpected_pass : Verdict::known_failure;
}

Check relative_check(std::string quantity, double measured, double reference, double tolerance,
                     std::string note) {
  Check c = make(std::move(quantity), Acceptance::relative, measured, std::move(note));
  c.reference = reference;
  c.error = std::abs(measured - reference) / std::abs(reference);
  c.lower = 0;
  c.upper = tolerance;
  c.passed = std::isfinite(c.error) && c.error <= tolerance;
  return c;
}

Check absolute_check(std::string quantity, double measured, double reference, double tolerance,
                     std::string note) {
  Check c = make(std::move(quantity), Acceptance::absolute, measured, std::move(note));
  c.reference = reference;
  c.error = std::abs(measured - reference);
  c.lower = 0;
  c.upper = tolerance;
  c.passed = std::isfinite(c.error) && c.error <= tolerance;
  return c;
}

Check at_most_check(std::string quantity, double measured, double upper, std::string note) {
  Check c = make(std::move(quantity), Acceptance::at_most, measured, std::move(note));
  c.upper = upper;
  c.passed = std::isfinite(measured) && measured <= upper;
  return c;
}

Check at_least_check(std::string quantity, double measured, double lower, std::string note) {
  Check c = make(std::move(quantity), Acceptance::at_least, measured, std::move(note));
  c.lower = lower;
  c.passed = std::isfinite(measured) && measured >= lower;
  return c;
}

Check within_check(std::string quantity, double measured, double lower, double upper,
                   std::string note) {
  Check c = make(std::move(quantity), Acceptance::within, measured, std::move(note));
  c.lower = lower;
  c.upper = upper;
  c.passed = std::isfinite(measured) && measured >= lower && measured <= upper;
  return c;
}

Check holds_check(std::string quantity, bool holds, std::string note) {
  Check c = make(std::move(quantity), Acceptance::holds, holds ? 1.0 : 0.0, std::move(note));
  c.passed = holds;
  return c;
}

Check report_only(std::string quantity, double measured, std::string note) {
  Check c = make(std::move(quantity), Acceptance::report, measured, std::move(note));
  c.passed = true;
  return c;
}

Check known_failure(Check check, std::string defect) {
  check.known_defect = std::move(defect);
  return check;
}

double observed_order(double coarse_error, double fine_error) {
  return std::log2(coarse_error / fine_error);
}

} // namespace talus
