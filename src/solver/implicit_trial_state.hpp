#pragma once
// The points' state at a trial increment of an implicit step: the step gradient
// dF = I + grad(du) (and in axisymmetry the hoop stretch 1 + u_r / r_n), F = dF F_n with
// F-bar's cell average where the case asks for it, and the material's Kirchhoff stress and
// tangent there. It is evaluated for a share of the points at one increment and kept until
// the increment changes: Newton asks for the residual and the tangent at the same increment.
#include "consolidation.hpp"
#include "f_bar_step.hpp"
#include "step_tangent.hpp"
#include "talus/core/errors.hpp"
#include "talus/core/parallel.hpp"
#include "talus/grid/particle_grid_map.hpp"
#include "talus/scene/pore_water.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/failure_hints.hpp"
#include "talus/solver/particle_share.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace talus {

template <int Dim, class Shape, bool Axisymmetric> class ImplicitTrialState {
  using V = Vec<Dim>;
  using M = Mat<Dim>;
  using Components = StepComponents<Dim, Axisymmetric>;

public:
  explicit ImplicitTrialState(Scene<Dim>& scene)
      : scene_(scene), consolidates_(scene.spec.consolidates()), f_bar_(scene.spec.solver.f_bar),
        f_bar_step_(scene.spec.solver.f_bar_out_of_plane) {
    resize();
  }

  /// Sized for the scene's points (after points were added or removed); nothing is kept.
  void resize() {
    const auto np = at(scene_.particles.size());
    F_.resize(np, Mat3::Identity());
    dF_.resize(np, M::Identity());
    if constexpr (Axisymmetric)
      hoop_.resize(np, 1.0);
    response_.resize(np);
    if (f_bar_)
      f_bar_step_.resize(static_cast<Index>(np));
    valid_ = false;
  }

  /// A new step on `map`'s nodes: F-bar's cells at the points' start positions, and the
  /// water's pore pressure u and gradient at each point there (scene.water at its progress),
  /// held through the step.
  void prepare(const ParticleGridMap<Dim, Shape>& map) {
    if (f_bar_)
      f_bar_step_.prepare(scene_.grid, scene_.particles, map.node_count());
    const PoreWater& water = scene_.water;
    if (consolidates_) { // the points' own pressure, set with each trial increment; the table's
      const auto& P = scene_.particles;
      const auto np = P.x.size();
      pore_pressure_.resize(np);
      excess_.resize(np);
      table_pressure_.resize(np);
      water_force_.resize(np);
      pressure_increment_.resize(np);
      pressure_gradient_.resize(np);
      for (std::size_t s = 0; s < np; ++s) {
        const double alpha = scene_.spec.materials[at(P.material[s])].flow->biot_coefficient;
        table_pressure_[s] = water.pore_pressure<Dim>(P.x[s]);
        water_force_[s] = alpha * P.volume[s] * water.pressure_gradient<Dim>(P.x[s]);
      }
    } else if (water.any()) {
      const auto& P = scene_.particles;
      pore_pressure_.resize(P.x.size());
      water_force_.resize(P.x.size());
      for (std::size_t s = 0; s < P.x.size(); ++s) {
        pore_pressure_[s] = water.pore_pressure<Dim>(P.x[s]);
        water_force_[s] = P.volume[s] * water.pressure_gradient<Dim>(P.x[s]);
      }
    }
    valid_ = false;
    rejection_.clear();
  }

  /// Why the step's last inadmissible trial state was refused (a material's message naming the
  /// point and the quantity), empty when none was.
  const std::string& last_rejection() const { return rejection_; }

  /// Whether the state is the share's at the increment du.
  bool matches(const ParticleShare& share, const Eigen::VectorXd& du) const {
    return valid_ && share_.begin == share.begin && share_.end == share.end &&
           du_.size() == du.size() && du_ == du;
  }

  /// Evaluates the share's points at the increment whose nodal values increment(n) gives (du
  /// names it for matches()). False when the increment is not admissible (a cell turned
  /// inside out, det F <= 0): Newton then backtracks, and the stepper may cut back.
  template <class Increment>
  bool update(const ParticleShare& share, const ParticleGridMap<Dim, Shape>& map,
              Increment&& increment, const Eigen::VectorXd& du) {
    const auto& P = scene_.particles;
    dF_.resize(at(P.size()));
    valid_ = false;
    if constexpr (Axisymmetric)
      hoop_.resize(at(P.size()));
    parallel_for(share.size(), [&](Index i) {
      const Index p = share.begin + i;
      M dF = M::Identity();
      [[maybe_unused]] double u_r = 0; // the radial increment at the point (axisymmetry)
      map.for_each_node_of(p, [&](Index n, double w, const V& grad) {
        const V u = increment(n);
        dF += u * grad.transpose();
        if constexpr (Axisymmetric)
          u_r += w * u[0];
      });
      dF_[at(p)] = dF;
      if constexpr (Axisymmetric)
        hoop_[at(p)] = 1.0 + u_r / radius_n(at(p)); // r_{n+1} / r_n
      F_[at(p)] = step_gradient(at(p)) * P.F[at(p)];
    });
    if (f_bar_ && !f_bar_step_.apply(
                      share, P, [&](Index q) { return step_gradient(at(q)); }, F_)) {
      rejection_ = "F-bar: a cell's mean volume change was not positive";
      return false;
    }
    try {
      for (std::size_t m = 0; m < scene_.materials.size(); ++m)
        scene_.materials[m]->response(points_of_material(m, share), F_, response_);
    } catch (const PointFailure& e) {
      rejection_ = e.what() + where_point_is(scene_, e.point());
      return false;
    } catch (const NumericalError& e) {
      rejection_ = e.what();
      return false;
    }
    valid_ = true;
    share_ = share;
    du_ = du;
    return true;
  }

  /// Consolidation (consolidation.hpp): the share's points' pore pressure at the trial
  /// increment, from the nodes' pressure at the step's start, node_pressure, and their
  /// increments dp(n): p = p_n + sum N dp, grad p = sum grad N (p_n + dp); the water table's
  /// part u of p presses as the water at rest does (the force alpha V_n grad u), the excess
  /// p - u as a stress, alpha (p - u) off the total (it does not press on a face that holds
  /// or loads the body: only free water does); flow per material.
  template <class Increment>
  void update_pore_pressure(const ParticleShare& share, const ParticleGridMap<Dim, Shape>& map,
                            const std::vector<double>& node_pressure, Increment&& dp,
                            const std::vector<PoreFlow>& flow) {
    const auto& P = scene_.particles;
    parallel_for(share.size(), [&](Index i) {
      const auto s = at(share.begin + i);
      double increment = 0;
      V gradient = V::Zero();
      map.for_each_node_of(share.begin + i, [&](Index n, double w, const V& grad) {
        const double dp_n = dp(n);
        increment += w * dp_n;
        gradient += (node_pressure[at(n)] + dp_n) * grad;
      });
      const double alpha = flow[at(P.material[s])].alpha;
      pressure_increment_[s] = increment;
      pressure_gradient_[s] = gradient;
      pore_pressure_[s] = P.pore_pressure[s] + increment;
      excess_[s] = alpha * (pore_pressure_[s] - table_pressure_[s]);
    });
  }

  /// Calls f(node, weight, force) for the nodes of point p's stencil with the point's force on
  /// the grid at its trial state: V0 G grad N, G = tau dF^-T the step's first Piola stress of
  /// the effective stress (and F-bar's volume ratio; in consolidation less the excess pore
  /// pressure's alpha (p - u) J), plus the hoop term V0 G33 N / r_n on the radial component;
  /// with water, plus N V grad u (pore_water.hpp), V = det(dF) V_n the point's current volume.
  template <class F>
  void for_each_internal_force(const ParticleGridMap<Dim, Shape>& map, Index p, F&& f) const {
    const auto s = at(p);
    const Mat3 dF = step_gradient(s);
    const Mat3 dF_inv = dF.inverse();
    const Mat3 G =
        scene_.particles.volume0[s] * volume_ratio(s) * balanced_kirchhoff(s) * dF_inv.transpose();
    const M G2 = G.topLeftCorner<Dim, Dim>();
    [[maybe_unused]] const double hoop_per_weight = Axisymmetric ? G(2, 2) / radius_n(s) : 0.0;
    // A dry step adds nothing per node (and stays bitwise the dry force).
    const auto visit = [&](auto wet) {
      [[maybe_unused]] const V water =
          wet ? V(dF.determinant() * water_force_[s]) : V::Zero().eval();
      map.for_each_node_of(p, [&](Index n, double w, const V& grad) {
        V force = G2 * grad;
        if constexpr (decltype(wet)::value)
          force += w * water;
        if constexpr (Axisymmetric)
          force[0] += hoop_per_weight * w;
        f(n, w, force);
      });
    };
    if (water_force_.empty())
      visit(std::false_type{});
    else
      visit(std::true_type{});
  }

  /// V_n grad u of point s: the water's force on the point per unit of det(dF) (zero in a dry
  /// step or above the water).
  V water_force(std::size_t s) const { return water_force_.empty() ? V::Zero() : water_force_[s]; }

  /// dG/d(dF) of point s at its trial state (step_tangent.hpp); with F-bar at fixed J_bar.
  StepTangent<Dim, Axisymmetric> point_step_tangent(std::size_t s) {
    return consolidates_ ? step_tangent_of(s, total_response(s)) : step_tangent_of(s, response_[s]);
  }

  /// The 3x3 trial step gradient of point s: its Dim x Dim block, and the hoop stretch.
  Mat3 step_gradient(std::size_t s) const {
    if constexpr (Axisymmetric)
      return Components::embed(dF_[s], hoop_[s]);
    return embedded<Dim>(dF_[s]);
  }
  const Particles<Dim>& points() const { return scene_.particles; }
  /// Point s's material, and its volume at the step's start V_n.
  int material(std::size_t s) const { return scene_.particles.material[s]; }
  double volume_n(std::size_t s) const { return scene_.particles.volume[s]; }
  /// The radius of point s at the step's start, r_n (axisymmetry; the points move at commit).
  double radius_n(std::size_t s) const { return scene_.particles.x[s][0]; }
  /// j_p / J_bar_c: the true current volume over the F-bar one (1 without F-bar).
  double volume_ratio(std::size_t s) const {
    return f_bar_ ? f_bar_step_.volume_ratio(static_cast<Index>(s)) : 1.0;
  }
  const Mat3& F(std::size_t s) const { return F_[s]; }
  /// The material's Kirchhoff stress (the effective one with water).
  const Mat3& kirchhoff(std::size_t s) const { return response_[s].kirchhoff; }
  /// The Kirchhoff stress the point's force takes: the material's, in consolidation less the
  /// excess pore pressure's alpha (p - u) J I.
  Mat3 balanced_kirchhoff(std::size_t s) const {
    Mat3 tau = response_[s].kirchhoff;
    if (consolidates_)
      tau.diagonal().array() -= excess_[s] * F_[s].determinant();
    return tau;
  }
  /// The pore pressure u of point s in this step (zero while no water acts).
  double pore_pressure(std::size_t s) const {
    return pore_pressure_.empty() ? 0.0 : pore_pressure_[s];
  }
  /// What point s's pore pressure takes off its total stress: alpha p (Biot's coefficient of
  /// a consolidating material; 1 for water at rest).
  double pore_stress(std::size_t s) const {
    const auto& flow = scene_.spec.materials[at(scene_.particles.material[s])].flow;
    return (consolidates_ ? flow->biot_coefficient : 1.0) * pore_pressure(s);
  }
  /// Consolidation: point s's trial increment of p, and grad p at the step's end.
  double pressure_increment(std::size_t s) const { return pressure_increment_[s]; }
  const V& pressure_gradient(std::size_t s) const { return pressure_gradient_[s]; }

  /// F-bar in the step, or null without it: its cells couple the tangent's points.
  FBarStep<Dim, Axisymmetric>* f_bar() { return f_bar_ ? &f_bar_step_ : nullptr; }

private:
  /// dG/d(dF) of point s for the stress and tangent r.
  StepTangent<Dim, Axisymmetric> step_tangent_of(std::size_t s, const StressTangent& r) {
    const Mat3& Fn = scene_.particles.F[s];
    if (!f_bar_)
      return step_tangent<Dim, Axisymmetric>(step_gradient(s), Fn, r);
    return f_bar_step_.step_tangent_of(static_cast<Index>(s), step_gradient(s), Fn, r);
  }

  /// balanced_kirchhoff(s) with its derivative (consolidation): d(J I)_ij / dF_kl =
  /// J F^-1_lk delta_ij.
  StressTangent total_response(std::size_t s) const {
    StressTangent r = response_[s];
    const double J = F_[s].determinant();
    const Mat3 inv = F_[s].inverse();
    r.kirchhoff = balanced_kirchhoff(s);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l)
          r.dtau_dF(3 * i + i, 3 * k + l) -= excess_[s] * J * inv(l, k);
    return r;
  }

  /// The share's points of material m (the material's list is ascending).
  std::span<const Index> points_of_material(std::size_t m, const ParticleShare& share) const {
    const auto& ids = scene_.particles_of_material[m];
    const auto first = std::lower_bound(ids.begin(), ids.end(), share.begin);
    return {first, std::lower_bound(first, ids.end(), share.end)};
  }

  Scene<Dim>& scene_;
  std::vector<double> pore_pressure_;      ///< per point: u in this step (with water only)
  std::vector<V> water_force_;             ///< per point: V_n grad u in this step (with water only)
  std::vector<double> excess_;             ///< per point: alpha (p - u) (consolidation only)
  std::vector<double> table_pressure_;     ///< per point: u in this step (consolidation only)
  std::vector<double> pressure_increment_; ///< per point: dp (consolidation only)
  std::vector<V> pressure_gradient_;       ///< per point: grad p at the step's end (consolidation)
  bool consolidates_ = false;
  bool f_bar_ = false; ///< F-bar volume averaging per cell (f_bar.hpp)
  FBarStep<Dim, Axisymmetric> f_bar_step_;
  std::vector<M> dF_;
  std::vector<double> hoop_; ///< per point: the trial hoop stretch (axisymmetry only)
  std::vector<Mat3> F_;
  std::vector<StressTangent> response_;
  bool valid_ = false;  ///< dF_, F_, response_ hold share_ at du_
  ParticleShare share_; ///< the points the state was last evaluated for
  Eigen::VectorXd du_;
  std::string rejection_; ///< see last_rejection
};

} // namespace talus
