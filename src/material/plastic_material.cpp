#include "talus/material/plastic_material.hpp"

#include "talus/core/errors.hpp"
#include "talus/core/parallel.hpp"
#include "talus/material/plasticity/drucker_prager.hpp"
#include "talus/material/plasticity/mohr_coulomb.hpp"
#include "talus/material/plasticity/tresca.hpp"
#include "talus/material/plasticity/von_mises.hpp"
#include "talus/material/principal_space.hpp"

#include <cmath>
#include <fmt/format.h>

namespace talus {

PlasticMaterial::PlasticMaterial(std::string name, double density, LameParameters lame,
                                 std::unique_ptr<PlasticModel> model, Kinematics kinematics,
                                 bool symmetric_tangent)
    : Material(std::move(name), density, lame), model_(std::move(model)), kinematics_(kinematics),
      symmetric_tangent_(symmetric_tangent) {}

void PlasticMaterial::reserve_points(std::size_t count) {
  if (converged_.size() >= count)
    return;
  converged_.resize(count, PlasticHistory::initial(kinematics_));
  trial_.resize(count, PlasticHistory::initial(kinematics_));
  converged_F_.resize(count, Mat3::Identity());
  trial_F_.resize(count, Mat3::Identity());
  trial_return_.resize(count, ReturnType::Elastic);
}

void PlasticMaterial::response(std::span<const Index> ids, std::span<const Mat3> F,
                               std::span<StressTangent> out) {
  reserve_points(F.size());
  parallel_for(static_cast<Index>(ids.size()), [&](Index k) {
    const auto p = static_cast<std::size_t>(ids[static_cast<std::size_t>(k)]);
    out[p] = evaluate_point(name(), p, [&] {
      return elastoplastic_response(*model_, kinematics_, F[p], converged_F_[p], converged_[p],
                                    trial_[p], &trial_return_[p]);
    });
    trial_F_[p] = F[p];
  });
}

void PlasticMaterial::commit(std::span<const Index> ids) {
  for (const Index id : ids) {
    const auto p = static_cast<std::size_t>(id);
    converged_[p] = trial_[p];
    converged_F_[p] = trial_F_[p];
  }
}

void PlasticMaterial::update_stress(std::span<const Index> ids, std::span<const Mat3> F,
                                    std::span<Mat3> stress) {
  reserve_points(F.size());
  parallel_for(static_cast<Index>(ids.size()), [&](Index k) {
    const auto p = static_cast<std::size_t>(ids[static_cast<std::size_t>(k)]);
    const Mat3& F3 = F[p];
    stress[p] = evaluate_point(name(), p, [&] {
      const double J = F3.determinant();
      if (!(J > 0.0))
        throw NumericalError(fmt::format("{}: det F = {:g} is not positive", model_->name(), J));
      return Mat3(elastoplastic_kirchhoff(*model_, kinematics_, F3, converged_F_[p], converged_[p],
                                          trial_[p], &trial_return_[p]) /
                  J);
    });
    converged_[p] = trial_[p];
    converged_F_[p] = F3;
  });
}

Vec3 PlasticMaterial::elastic_strain(std::size_t p) const {
  const Vec3 values = spectral_decomposition(converged_[p].elastic).values;
  return kinematics_ == Kinematics::FiniteStrain ? Vec3(0.5 * values.array().log().matrix())
                                                 : values;
}

double PlasticMaterial::stored_energy(std::span<const Index> ids, std::span<const Mat3>,
                                      std::span<const double> volume0) const {
  return parallel_sum(static_cast<Index>(ids.size()), [&](Index k) {
    const auto p = static_cast<std::size_t>(ids[static_cast<std::size_t>(k)]);
    if (p >= converged_.size())
      return 0.0; // never evaluated: unstrained
    const Vec3 e = elastic_strain(p);
    return volume0[p] * (lame().mu * e.squaredNorm() + 0.5 * lame().lambda * e.sum() * e.sum());
  });
}

void PlasticMaterial::plastic_strain(std::span<const Index> ids, std::span<double> out) const {
  for (const Index id : ids) {
    const auto p = static_cast<std::size_t>(id);
    out[p] = p < converged_.size() ? converged_[p].kappa : 0.0;
  }
}

void PlasticMaterial::set_initial_stress(std::span<const Index> ids, std::span<const Mat3> stress) {
  reserve_points(stress.size());
  // At F = I the Kirchhoff and Cauchy stresses agree, and both kinematics store the elastic
  // strain that the elastic law maps onto the given stress: eps_e = C^-1 sigma in principal
  // values (finite strain keeps b_e = exp(2 eps_e)).
  const LameParameters& l = lame();
  const double bulk = l.lambda + 2.0 * l.mu / 3.0;
  for (const Index id : ids) {
    const auto p = static_cast<std::size_t>(id);
    const SpectralDecomposition s = spectral_decomposition(stress[p]);
    const Vec3 sigma = s.values;
    if (model_->yield_function(sigma, 0.0) > 1e-12 * std::max(1.0, sigma.cwiseAbs().maxCoeff()))
      throw InputError(SourceLocation{},
                       fmt::format("material '{}': the initial stress of point {} (principal "
                                   "{:.6g}, {:.6g}, {:.6g} Pa) lies outside the {} yield surface",
                                   name(), p, sigma[0], sigma[1], sigma[2], model_->name()));
    const double mean = sigma.sum() / 3.0;
    const Vec3 eps =
        Vec3::Constant(mean / (3.0 * bulk)) + (sigma - Vec3::Constant(mean)) / (2.0 * l.mu);
    const Vec3 stored =
        kinematics_ == Kinematics::FiniteStrain ? Vec3((2.0 * eps).array().exp().matrix()) : eps;
    converged_[p].elastic = from_principal(s, stored);
    converged_[p].kappa = 0.0;
    converged_F_[p] = Mat3::Identity();
    trial_[p] = converged_[p];
  }
}

void PlasticMaterial::append_copies(Index old_count, std::span<const Index> sources) {
  if (converged_.empty())
    return; // never evaluated: every point, old or new, starts from the initial state
  reserve_points(static_cast<std::size_t>(old_count));
  for (const Index id : sources) {
    const auto p = static_cast<std::size_t>(id);
    converged_.push_back(converged_[p]);
    trial_.push_back(trial_[p]);
    converged_F_.push_back(converged_F_[p]);
    trial_F_.push_back(trial_F_[p]);
    trial_return_.push_back(trial_return_[p]);
  }
}

std::unique_ptr<PlasticModel> make_plastic_model(const MaterialSpec& spec) {
  const LameParameters lame = checked_lame_parameters(spec.youngs_modulus, spec.poisson_ratio);
  FrictionalStrengthParameters strength;
  strength.cohesion = spec.cohesion;
  strength.friction_angle = spec.friction_angle;
  strength.dilation_angle = spec.dilation_angle;
  if (spec.residual)
    strength.residual = ResidualStrength{spec.residual->cohesion, spec.residual->friction_angle,
                                         spec.residual->plastic_strain};
  switch (spec.model) {
  case MaterialModel::VonMises:
    return std::make_unique<VonMises>(lame, spec.yield_stress, spec.hardening_modulus);
  case MaterialModel::Tresca:
    return std::make_unique<Tresca>(lame, spec.cohesion);
  case MaterialModel::MohrCoulomb:
    return std::make_unique<MohrCoulomb>(lame, strength);
  case MaterialModel::DruckerPrager:
    return std::make_unique<DruckerPrager>(lame, strength);
  default:
    throw std::logic_error("make_plastic_model: '" + spec.name + "' is an elastic model");
  }
}

bool nonsymmetric_tangent(const MaterialSpec& spec) {
  const bool frictional =
      spec.model == MaterialModel::MohrCoulomb || spec.model == MaterialModel::DruckerPrager;
  return frictional && (spec.dilation_angle != spec.friction_angle || spec.residual.has_value());
}

namespace {
constexpr std::size_t kHistoryValues = 9 + 1 + 9 + 1;
} // namespace

std::vector<double> PlasticMaterial::history() const {
  std::vector<double> out;
  out.reserve(kHistoryValues * converged_.size());
  for (std::size_t p = 0; p < converged_.size(); ++p) {
    out.insert(out.end(), converged_[p].elastic.data(), converged_[p].elastic.data() + 9);
    out.push_back(converged_[p].kappa);
    out.insert(out.end(), converged_F_[p].data(), converged_F_[p].data() + 9);
    out.push_back(static_cast<double>(trial_return_[p]));
  }
  return out;
}

void PlasticMaterial::restore_history(std::span<const double> values) {
  if (values.size() % kHistoryValues != 0)
    throw std::runtime_error(fmt::format("material '{}': a plastic history of {} values is not "
                                         "{} per point",
                                         name(), values.size(), kHistoryValues));
  const std::size_t n = values.size() / kHistoryValues;
  converged_.assign(n, PlasticHistory::initial(kinematics_));
  converged_F_.assign(n, Mat3::Identity());
  trial_return_.assign(n, ReturnType::Elastic);
  for (std::size_t p = 0; p < n; ++p) {
    const double* v = values.data() + kHistoryValues * p;
    converged_[p].elastic = Eigen::Map<const Mat3>(v);
    converged_[p].kappa = v[9];
    converged_F_[p] = Eigen::Map<const Mat3>(v + 10);
    trial_return_[p] = static_cast<ReturnType>(static_cast<int>(v[19]));
  }
  trial_ = converged_;
  trial_F_ = converged_F_;
}

} // namespace talus
