#pragma once
// The words a case file may use for its enumerated keys, in one place: the case reader validates
// against these tables and `talus info` prints them, so the two cannot drift apart.
#include "talus/spec/case_spec.hpp"

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace talus {

template <class E> using Choices = std::vector<std::pair<std::string, E>>;

const Choices<AnalysisType>& analysis_choices();          ///< analysis, stages[i].analysis
const Choices<Geometry>& geometry_choices();              ///< geometry (2D)
const Choices<MaterialModel>& material_model_choices();   ///< materials[i].model
const Choices<ShapeFunction>& shape_function_choices();   ///< solver.shape
const Choices<UpdateScheme>& update_scheme_choices();     ///< solver.scheme (explicit)
const Choices<TransferScheme>& transfer_scheme_choices(); ///< solver.transfer
const Choices<StrengthReductionMode>& strength_reduction_mode_choices(); ///< its `mode`
const Choices<StrengthReductionFlow>& strength_reduction_flow_choices(); ///< its `flow_rule`
/// bodies[i].shape of a 2D case (rectangle, disc, polygon) or a 3D one (box, sphere, cylinder,
/// prism).
const Choices<BodyShape>& body_shape_choices(int dimension);
const Choices<OutputField>& output_field_choices();             ///< output.fields
const Choices<PlausibilityCheck>& plausibility_check_choices(); ///< silence_warnings

/// The words of a table, in its order.
template <class E> std::vector<std::string> choice_names(const Choices<E>& choices) {
  std::vector<std::string> names;
  names.reserve(choices.size());
  for (const auto& [word, value] : choices)
    names.push_back(word);
  return names;
}

/// The word of `value` in a table (as the case file writes it; fos.json echoes it back).
template <class E> const std::string& choice_word(const Choices<E>& choices, E value) {
  for (const auto& [word, v] : choices)
    if (v == value)
      return word;
  throw std::logic_error("choice_word: a value missing from its table");
}

/// The material model words of the elastic (plastic = false) or elasto-plastic models.
std::vector<std::string> material_model_names(bool plastic);

} // namespace talus
