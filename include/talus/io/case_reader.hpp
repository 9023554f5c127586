#pragma once
// Reads a YAML case file into a CaseSpec. Every problem is reported as an InputError naming
// file:line:column and the key path; nothing is written before the whole case validated.
#include "talus/spec/case_spec.hpp"

#include <string>
#include <vector>

namespace talus {

/// Parses and validates `path`, applying `overrides` ("key.path=value", e.g.
/// "materials[0].youngs_modulus=2e5" or "solver.shape=linear") before validation, so an override
/// gets the same checks as the file. Throws InputError on the first problem.
CaseSpec read_case_file(const std::string& path, const std::vector<std::string>& overrides = {});

/// Same, from text already in memory (used by tests and by `talus verify`). `label` names the
/// source in messages.
CaseSpec read_case_text(const std::string& text, const std::string& label,
                        const std::vector<std::string>& overrides = {});

} // namespace talus

namespace talus {

/// Where two cases differ, each given as its text and --set overrides (both already read
/// without error): the key paths ("time.end_time", "materials[0].cohesion") whose values
/// differ or that only one case has. Comments and layout are not differences; values are
/// compared as written ("1e3" and "1000" differ).
std::vector<std::string> case_differences(const std::string& text_a,
                                          const std::vector<std::string>& overrides_a,
                                          const std::string& text_b,
                                          const std::vector<std::string>& overrides_b);

} // namespace talus
