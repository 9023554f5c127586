#pragma once
// Plausibility warnings: magnitudes of a valid case that lie far from what soils and rocks have,
// or out of scale with the case's own weight. Most are unit mistakes (kPa typed where Talus takes
// Pa, a unit weight typed as a density, an angle in radians). They are warnings, not errors: a
// benchmark in non-dimensional units is valid input, and the case's `silence_warnings` list
// names the checks it accepts. `talus check`, `run`, `fos` and `adapt` print them.
#include "talus/spec/case_spec.hpp"

#include <string>
#include <vector>

namespace talus {

struct PlausibilityWarning {
  PlausibilityCheck check; ///< the check that fired (its word silences it)
  SourceLocation where;    ///< the value it is about
  std::string message;     ///< what looks wrong and the likely mistake
};

/// The warnings of a case that its `silence_warnings` does not accept, in the order of the case.
std::vector<PlausibilityWarning> plausibility_warnings(const CaseSpec& spec);

/// One line: "talus: warning: <file:line:column: key '...'>: <message> (...how to accept it)".
std::string describe(const PlausibilityWarning& warning);

} // namespace talus
