#include "talus/material/material.hpp"

#include "talus/core/errors.hpp"
#include "talus/core/parallel.hpp"
#include "talus/material/hyperelastic.hpp"
#include "talus/material/plastic_material.hpp"
#include "talus/material/principal_space.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

namespace talus {

double Material::wave_speed() const {
  return std::sqrt(lame_.p_wave_modulus() / density_);
}

void Material::plastic_strain(std::span<const Index> ids, std::span<double> out) const {
  for (const Index p : ids)
    out[static_cast<std::size_t>(p)] = 0.0;
}

void Material::restore_history(std::span<const double> values) {
  if (!values.empty())
    throw std::runtime_error(fmt::format(
        "material '{}': the checkpoint holds a plastic history, but the model has none", name()));
}

void Material::set_initial_stress(std::span<const Index> ids, std::span<const Mat3>) {
  if (!ids.empty())
    throw InputError(SourceLocation{},
                     fmt::format("material '{}': an initial stress needs a model with an elastic "
                                 "strain state (von_mises, tresca, mohr_coulomb, drucker_prager); "
                                 "an elastic model's stress follows from F alone",
                                 name()));
}

namespace {

/// det F, or NumericalError naming the model when it is not positive (the batch adds the
/// material and the point: evaluate_point).
double checked_jacobian(const Mat3& F, const char* model) {
  const double J = F.determinant();
  if (!(J > 0.0))
    throw NumericalError(fmt::format("{}: det F = {:g} is not positive", model, J));
  return J;
}

} // namespace

Mat3 LinearElastic::stress(const Mat3& F) const {
  const double J = checked_jacobian(F, "linear elastic");
  return linear_elastic_kirchhoff(F, lame()) / J;
}

StressTangent LinearElastic::response(const Mat3& F) const {
  return linear_elastic_response(F, lame());
}

double LinearElastic::energy_density(const Mat3& F) const {
  const Mat3 eps = 0.5 * (F + F.transpose()) - Mat3::Identity();
  return 0.5 * lame().lambda * eps.trace() * eps.trace() + lame().mu * eps.squaredNorm();
}

Mat3 NeoHookean::stress(const Mat3& F) const {
  const double J = checked_jacobian(F, "neo-Hookean");
  return neo_hookean_kirchhoff(F, lame()) / J;
}

StressTangent NeoHookean::response(const Mat3& F) const {
  checked_jacobian(F, "neo-Hookean");
  return neo_hookean_response(F, lame());
}

double NeoHookean::energy_density(const Mat3& F) const {
  const double J = F.determinant();
  const double lnJ = std::log(J);
  return 0.5 * lame().mu * ((F.transpose() * F).trace() - 3.0) - lame().mu * lnJ +
         0.5 * lame().lambda * lnJ * lnJ;
}

Mat3 Hencky::stress(const Mat3& F) const {
  const double J = checked_jacobian(F, "Hencky");
  return hencky_kirchhoff(F, lame()) / J;
}

StressTangent Hencky::response(const Mat3& F) const {
  checked_jacobian(F, "Hencky");
  return hencky_response(F, lame());
}

double Hencky::energy_density(const Mat3& F) const {
  // b cannot see an inverted F: report it as NaN, like the ln J of the neo-Hookean energy
  if (!(F.determinant() > 0.0))
    return std::numeric_limits<double>::quiet_NaN();
  // principal logarithmic strains e_a = ln(x_a) / 2 from the eigenvalues x_a of b = F F^T
  const Vec3 e = 0.5 * spectral_decomposition(F * F.transpose()).values.array().log().matrix();
  return lame().mu * e.squaredNorm() + 0.5 * lame().lambda * e.sum() * e.sum();
}

std::unique_ptr<Material> make_material(const MaterialSpec& spec) {
  const auto lame = LameParameters::from_young_poisson(spec.youngs_modulus, spec.poisson_ratio);
  switch (spec.model) {
  case MaterialModel::LinearElastic:
    return std::make_unique<LinearElastic>(spec.name, spec.density, lame);
  case MaterialModel::NeoHookean:
    return std::make_unique<NeoHookean>(spec.name, spec.density, lame);
  case MaterialModel::Hencky:
    return std::make_unique<Hencky>(spec.name, spec.density, lame);
  case MaterialModel::VonMises:
  case MaterialModel::Tresca:
  case MaterialModel::MohrCoulomb:
  case MaterialModel::DruckerPrager:
    return std::make_unique<PlasticMaterial>(
        spec.name, spec.density, lame, make_plastic_model(spec),
        spec.small_strain ? Kinematics::SmallStrain : Kinematics::FiniteStrain,
        !nonsymmetric_tangent(spec));
  }
  throw std::logic_error("unknown material model");
}

bool symmetric_implicit_tangent(const CaseSpec& spec) {
  return !spec.solver.f_bar && !spec.water &&
         std::none_of(spec.materials.begin(), spec.materials.end(), nonsymmetric_tangent);
}

} // namespace talus
