#pragma once
// What the tests of a section's input refuse with (test_water_input.cpp,
// test_consolidation.cpp): the InputError that reading and building a 2D case gives.
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/scene/scene.hpp"

#include <gtest/gtest.h>

#include <string>

namespace talus::test_support {

/// The InputError reading (and building) the case gives, or a failure.
inline InputError scene_error_of(const std::string& text) {
  try {
    build_scene<2>(read_case_text(text, "case.yaml"));
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "expected an InputError for\n" << text;
  return InputError({}, "");
}

inline bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

} // namespace talus::test_support
