#pragma once
// An elasto-plastic material: a return map in principal space (plasticity/plastic_model.hpp)
// driven through finite-strain (Hencky, exponential map) or small-strain kinematics
// (plasticity/elastoplastic_response.hpp), with a history per point: the elastic strain
// (b_e or eps_e), the accumulated plastic shear strain and the deformation gradient it was
// stored with. The implicit solver evaluates trial states on every Newton iterate and accepts
// them with commit() once the step has converged; the explicit solver's update_stress()
// evaluates and accepts in one go. Only materials of this kind allocate history.
#include "talus/material/material.hpp"
#include "talus/material/plasticity/elastoplastic_response.hpp"
#include "talus/spec/case_spec.hpp"

#include <memory>
#include <vector>

namespace talus {

class PlasticMaterial final : public Material {
public:
  PlasticMaterial(std::string name, double density, LameParameters lame,
                  std::unique_ptr<PlasticModel> model, Kinematics kinematics,
                  bool symmetric_tangent);

  void update_stress(std::span<const Index> ids, std::span<const Mat3> F,
                     std::span<Mat3> stress) override;
  double stored_energy(std::span<const Index> ids, std::span<const Mat3> F,
                       std::span<const double> volume0) const override;
  void response(std::span<const Index> ids, std::span<const Mat3> F,
                std::span<StressTangent> out) override;
  void commit(std::span<const Index> ids) override;
  bool symmetric_tangent() const override { return symmetric_tangent_; }
  bool plastic() const override { return true; }
  void plastic_strain(std::span<const Index> ids, std::span<double> out) const override;
  void set_initial_stress(std::span<const Index> ids, std::span<const Mat3> stress) override;
  void append_copies(Index old_count, std::span<const Index> sources) override;
  /// Per point: the elastic strain (9), kappa, the F it was stored with (9), the last return.
  std::vector<double> history() const override;
  void restore_history(std::span<const double> values) override;

  const PlasticModel& model() const { return *model_; }
  /// Swaps the return map for one of the same material with another strength (a stage's
  /// strength factor). The history is kept: the next evaluation returns a stress that lies
  /// outside the new surface onto it.
  void replace_model(std::unique_ptr<PlasticModel> model) { model_ = std::move(model); }
  /// The return the last evaluation took at point p (elastic, surface, edge, apex).
  ReturnType last_return(Index p) const { return trial_return_[static_cast<std::size_t>(p)]; }

private:
  /// Sizes the history for `count` points (the scene's particle count), new points unstrained.
  void reserve_points(std::size_t count);
  /// Principal elastic strains of the converged history of point p.
  Vec3 elastic_strain(std::size_t p) const;

  std::unique_ptr<PlasticModel> model_;
  Kinematics kinematics_;
  bool symmetric_tangent_;
  std::vector<PlasticHistory> converged_, trial_;
  std::vector<Mat3> converged_F_, trial_F_;
  std::vector<ReturnType> trial_return_;
};

/// The return map of an elasto-plastic material spec (von_mises, tresca, mohr_coulomb,
/// drucker_prager). Throws InputError naming the offending parameter key.
std::unique_ptr<PlasticModel> make_plastic_model(const MaterialSpec& spec);

/// Whether the spec's consistent tangent can be nonsymmetric: non-associated flow (psi < phi)
/// or softening.
bool nonsymmetric_tangent(const MaterialSpec& spec);

} // namespace talus
