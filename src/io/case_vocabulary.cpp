#include "talus/io/case_vocabulary.hpp"

namespace talus {

const char* face_name(int face) {
  static const char* const names[kMaxFaces] = {"x_min", "x_max", "y_min",
                                               "y_max", "z_min", "z_max"};
  return names[face];
}

const Choices<AnalysisType>& analysis_choices() {
  static const Choices<AnalysisType> c{{"explicit", AnalysisType::Explicit},
                                       {"implicit_quasistatic", AnalysisType::ImplicitQuasistatic},
                                       {"implicit_dynamic", AnalysisType::ImplicitDynamic}};
  return c;
}

const Choices<Geometry>& geometry_choices() {
  static const Choices<Geometry> c{{"plane_strain", Geometry::PlaneStrain},
                                   {"axisymmetric", Geometry::Axisymmetric}};
  return c;
}

const Choices<MaterialModel>& material_model_choices() {
  static const Choices<MaterialModel> c{{"linear_elastic", MaterialModel::LinearElastic},
                                        {"neo_hookean", MaterialModel::NeoHookean},
                                        {"hencky", MaterialModel::Hencky},
                                        {"von_mises", MaterialModel::VonMises},
                                        {"tresca", MaterialModel::Tresca},
                                        {"mohr_coulomb", MaterialModel::MohrCoulomb},
                                        {"drucker_prager", MaterialModel::DruckerPrager}};
  return c;
}

const Choices<ShapeFunction>& shape_function_choices() {
  static const Choices<ShapeFunction> c{
      {"gimp", ShapeFunction::Gimp},         {"linear", ShapeFunction::Linear},
      {"cpgimp", ShapeFunction::CpGimp},     {"bspline2", ShapeFunction::BSpline2},
      {"bspline3", ShapeFunction::BSpline3}, {"cpdi", ShapeFunction::Cpdi}};
  return c;
}

const Choices<UpdateScheme>& update_scheme_choices() {
  static const Choices<UpdateScheme> c{
      {"usl", UpdateScheme::USL}, {"usf", UpdateScheme::USF}, {"musl", UpdateScheme::MUSL}};
  return c;
}

const Choices<TransferScheme>& transfer_scheme_choices() {
  static const Choices<TransferScheme> c{{"flip", TransferScheme::Flip},
                                         {"apic", TransferScheme::Apic}};
  return c;
}

const Choices<StrengthReductionMode>& strength_reduction_mode_choices() {
  static const Choices<StrengthReductionMode> c{
      {"trials", StrengthReductionMode::Trials},
      {"incremental", StrengthReductionMode::Incremental}};
  return c;
}

const Choices<StrengthReductionFlow>& strength_reduction_flow_choices() {
  static const Choices<StrengthReductionFlow> c{{"as_given", StrengthReductionFlow::AsGiven},
                                                {"davis", StrengthReductionFlow::Davis}};
  return c;
}

const Choices<BodyShape>& body_shape_choices(int dimension) {
  static const Choices<BodyShape> plane{{"rectangle", BodyShape::Rectangle},
                                        {"disc", BodyShape::Disc},
                                        {"polygon", BodyShape::Polygon}};
  static const Choices<BodyShape> solid{{"box", BodyShape::Rectangle},
                                        {"sphere", BodyShape::Disc},
                                        {"cylinder", BodyShape::Cylinder},
                                        {"prism", BodyShape::Polygon}};
  return dimension == 3 ? solid : plane;
}

const Choices<OutputField>& output_field_choices() {
  static const Choices<OutputField> c{{"velocity", OutputField::Velocity},
                                      {"mass", OutputField::Mass},
                                      {"volume", OutputField::Volume},
                                      {"F", OutputField::DeformationGradient},
                                      {"stress", OutputField::Stress},
                                      {"material", OutputField::Material},
                                      {"plastic_strain", OutputField::PlasticStrain},
                                      {"pore_pressure", OutputField::PorePressure},
                                      {"effective_stress", OutputField::EffectiveStress},
                                      {"reference_position", OutputField::ReferencePosition}};
  return c;
}

const Choices<PlausibilityCheck>& plausibility_check_choices() {
  static const Choices<PlausibilityCheck> c{
      {"density", PlausibilityCheck::Density},
      {"youngs_modulus", PlausibilityCheck::YoungsModulus},
      {"strength", PlausibilityCheck::Strength},
      {"friction_angle", PlausibilityCheck::FrictionAngle},
      {"load", PlausibilityCheck::Load},
      {"gravity", PlausibilityCheck::Gravity},
      {"displacement", PlausibilityCheck::Displacement},
      {"permeability", PlausibilityCheck::Permeability},
      {"consolidation_step", PlausibilityCheck::ConsolidationStep}};
  return c;
}

std::vector<std::string> material_model_names(bool plastic) {
  std::vector<std::string> names;
  for (const auto& [word, model] : material_model_choices())
    if (is_plastic(model) == plastic)
      names.push_back(word);
  return names;
}

} // namespace talus
