#pragma once
// Constitutive models. A model is evaluated for a whole batch of particles per call (one
// virtual call per material per step, never per particle). Kinematics enter as the full 3x3
// deformation gradient the particles carry (plane strain: the in-plane block with F33 = 1).
#include "talus/core/errors.hpp"
#include "talus/core/parallel.hpp"
#include "talus/core/types.hpp"
#include "talus/material/stress_tangent.hpp"
#include "talus/spec/case_spec.hpp"

#include <memory>
#include <span>
#include <string>
#include <vector>

namespace talus {

struct LameParameters {
  double lambda = 0;
  double mu = 0;
  static LameParameters from_young_poisson(double E, double nu) {
    return {E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))};
  }
  double p_wave_modulus() const { return lambda + 2.0 * mu; }
  double young_modulus() const { return mu * (3.0 * lambda + 2.0 * mu) / (lambda + mu); }
};

class Material {
public:
  Material(std::string name, double density, LameParameters lame)
      : name_(std::move(name)), density_(density), lame_(lame) {}
  virtual ~Material() = default;

  const std::string& name() const { return name_; }
  double density() const { return density_; }
  const LameParameters& lame() const { return lame_; }
  /// Speed of the fastest (pressure) wave at the reference state, m/s; used for the CFL step.
  double wave_speed() const;

  /// Cauchy stress for every particle in `ids` from its deformation gradient: the explicit
  /// solver's material update. A model with history accepts the new state at once.
  virtual void update_stress(std::span<const Index> ids, std::span<const Mat3> F,
                             std::span<Mat3> stress) = 0;
  /// The stored (elastic strain) energy of a batch of points at the deformation gradients F
  /// (for a model with history: of its converged elastic strain).
  virtual double stored_energy(std::span<const Index> ids, std::span<const Mat3> F,
                               std::span<const double> volume0) const = 0;
  /// Kirchhoff stress and consistent tangent dtau/dF at the trial deformation gradients
  /// F[ids[k]] (full 3x3), written to out[ids[k]]: the implicit solver's material update. A
  /// model with history evaluates the trial from its converged state and keeps it as a trial
  /// until commit().
  virtual void response(std::span<const Index> ids, std::span<const Mat3> F,
                        std::span<StressTangent> out) = 0;

  // --- history (elasto-plastic models); elastic models keep the defaults -------------------
  /// Accepts the trial states of the last response() for the points in ids (implicit solver,
  /// after a converged step).
  virtual void commit(std::span<const Index> /*ids*/) {}
  /// Whether the consistent tangent may be nonsymmetric (non-associated flow, softening).
  virtual bool symmetric_tangent() const { return true; }
  /// Whether the model carries a plastic history (and a plastic-strain output field).
  virtual bool plastic() const { return false; }
  /// Accumulated equivalent plastic shear strain of the points in ids, into out[ids[k]].
  virtual void plastic_strain(std::span<const Index> ids, std::span<double> out) const;
  /// Starts the points in ids from the Cauchy stresses stress[ids[k]] at F = I (geostatic
  /// initial stress). Throws InputError naming the point if a stress is not admissible.
  virtual void set_initial_stress(std::span<const Index> ids, std::span<const Mat3> stress);
  /// The scene appended points old_count, old_count + 1, ... as copies of the points in
  /// `sources` (material-point splitting): per-point history is copied the same way. History
  /// is indexed by the scene's point index, so this covers every point, of any material.
  virtual void append_copies(Index /*old_count*/, std::span<const Index> /*sources*/) {}
  /// The converged per-point history, flattened, for a checkpoint (empty: nothing to keep).
  virtual std::vector<double> history() const { return {}; }
  /// Restores what history() returned (talus run --resume). Throws std::runtime_error if the
  /// values do not fit this model.
  virtual void restore_history(std::span<const double> values);

private:
  std::string name_;
  double density_;
  LameParameters lame_;
};

/// The batch loop shared by the elastic laws, whose stress depends on F alone: Law::stress is
/// called directly (no virtual call per particle).
/// Evaluates point p of a material's batch: a NumericalError of the model becomes a PointFailure
/// naming the material and the point, so a failed step says where it went wrong.
template <class F>
decltype(auto) evaluate_point(const std::string& material, std::size_t p, F&& evaluate) {
  try {
    return evaluate();
  } catch (const PointFailure&) {
    throw;
  } catch (const NumericalError& e) {
    throw PointFailure(static_cast<long long>(p),
                       "material '" + material + "', point " + std::to_string(p) + ": " + e.what());
  }
}

template <class Law> class ElasticMaterial : public Material {
public:
  using Material::Material;
  void update_stress(std::span<const Index> ids, std::span<const Mat3> F,
                     std::span<Mat3> stress_out) final {
    const auto& law = static_cast<const Law&>(*this);
    parallel_for(static_cast<Index>(ids.size()), [&](Index k) {
      const auto p = static_cast<std::size_t>(ids[static_cast<std::size_t>(k)]);
      stress_out[p] = evaluate_point(law.name(), p, [&] { return law.stress(F[p]); });
    });
  }
  double stored_energy(std::span<const Index> ids, std::span<const Mat3> F,
                       std::span<const double> volume0) const final {
    const auto& law = static_cast<const Law&>(*this);
    return parallel_sum(static_cast<Index>(ids.size()), [&](Index k) {
      const auto s = static_cast<std::size_t>(ids[static_cast<std::size_t>(k)]);
      return volume0[s] * law.Law::energy_density(F[s]);
    });
  }
  void response(std::span<const Index> ids, std::span<const Mat3> F,
                std::span<StressTangent> out) final {
    const auto& law = static_cast<const Law&>(*this);
    parallel_for(static_cast<Index>(ids.size()), [&](Index k) {
      const auto p = static_cast<std::size_t>(ids[static_cast<std::size_t>(k)]);
      out[p] = evaluate_point(law.name(), p, [&] { return law.response(F[p]); });
    });
  }
};

/// Small-strain linear elasticity: energy W(eps), eps = sym(F) - I, P = dW/dF,
/// sigma = P F^T / J (hyperelastic.hpp). Exact for small displacements; not objective under
/// large rotation (use neo_hookean or hencky there); J <= 0 is an error.
class LinearElastic final : public ElasticMaterial<LinearElastic> {
public:
  using ElasticMaterial::ElasticMaterial;
  Mat3 stress(const Mat3& F) const;
  StressTangent response(const Mat3& F) const;
  double energy_density(const Mat3& F) const;
};

/// Compressible neo-Hookean: sigma = mu/J (b - I) + lambda ln(J)/J I,
/// psi = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2. Objective; J <= 0 is an error.
class NeoHookean final : public ElasticMaterial<NeoHookean> {
public:
  using ElasticMaterial::ElasticMaterial;
  Mat3 stress(const Mat3& F) const;
  StressTangent response(const Mat3& F) const;
  double energy_density(const Mat3& F) const;
};

/// Hencky (logarithmic-strain) hyperelasticity: tau = lambda tr(e) I + 2 mu e with
/// e = 1/2 ln(b), b = F F^T, sigma = tau / J; psi = mu e:e + lambda/2 (tr e)^2. Objective, and
/// linear in the log strain, so it stays well behaved at large stretch; J <= 0 is an error.
class Hencky final : public ElasticMaterial<Hencky> {
public:
  using ElasticMaterial::ElasticMaterial;
  Mat3 stress(const Mat3& F) const;
  StressTangent response(const Mat3& F) const;
  double energy_density(const Mat3& F) const;
};

std::unique_ptr<Material> make_material(const MaterialSpec& spec);

/// Whether a case's implicit tangent is symmetric, so that Cholesky can solve it: no F-bar (it
/// couples a cell's points through their mean volume change), no material whose tangent is
/// not (non-associated flow, softening), and no water (its pressure gradient acts on the
/// points' current volume: water_stiffness.hpp).
bool symmetric_implicit_tangent(const CaseSpec& spec);

} // namespace talus
