#pragma once
// Biot consolidation in an implicit step (docs/architecture.md, "Consolidation"): the pore
// pressure p is a nodal unknown beside the displacement, coupled to the skeleton by
//   balance:  the points' effective stress less alpha (p - u) I, the excess over the water
//             table's u, with the body force -alpha grad u (the volume form of the free water,
//             implicit_trial_state.hpp), on the current volume;
//   mass:     alpha (J - 1) + dp / M + dt div q = 0 per unit of the step's start volume, backward
//             Euler, Darcy's q = -(k / gamma_w) (grad p - gamma_w g / |g|) on the step's start
//             configuration (with a water table p is the whole pore pressure; without one the
//             excess over a hydrostatic state, and the gravity term is dropped).
// Per node i of a point's stencil (N_i its weight, V_n its volume at the step's start) the
// mass balance is
//   r_i = s V_n [N_i (alpha (J - 1) + dp_p / M) + dt (k / gamma_w) grad N_i . (grad p - h)],
// dp_p = sum_j N_j dp_j the point's increment, grad p = sum_j grad N_j p_j at the step's end,
// h the gravity head. s, the pressure unit, makes the rows a force and the unknowns a length
// (p = s x): Newton's norms and the pivots then see one scale, whatever the units of p. The
// length is the cell, or in a step long enough for the water to flow farther than a cell the
// flow's own (s^2 dt k / gamma_w = M_c): otherwise the flow's block outweighs the skeleton's by
// c_v dt / h^2, and Newton stalls at that many times round-off (a steady seepage step).
#include "talus/core/types.hpp"
#include "talus/material/material.hpp"
#include "talus/spec/case_spec.hpp"
#include "water_stiffness.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace talus {

/// A material's pore flow in the step's terms.
struct PoreFlow {
  double alpha = 1;    ///< Biot's coefficient
  double storage = 0;  ///< 1 / M, 1/Pa
  double mobility = 0; ///< k / gamma_w, m^2 / (Pa s)
  /// The pressure projection's tau = f alpha^2 / (2 G), 1/Pa (pressure_projection.hpp).
  double projection = 0;
};

template <int Dim> struct Consolidation {
  std::vector<PoreFlow> flow; ///< per material
  /// gamma_w g / |g| with a water table (hydrostatic p does not flow), else zero; of this step:
  /// the share of the weight it has reached (a first stage whose weight grows from zero grows
  /// the water's with it, as it grows the table's pressure).
  Vec<Dim> gravity_head = Vec<Dim>::Zero();
  Vec<Dim> full_gravity_head = Vec<Dim>::Zero(); ///< at the full weight
  double pressure_unit = 1; ///< s: Pa per unit of the pressure unknown, set per step
  double flow_time = 0;     ///< s, how long the water flows in the step: dt, 0 if undrained
  double stiffest = 0;      ///< the largest constrained modulus M_c of the materials
  double mobility = 0;      ///< the largest k / gamma_w

  /// s for a step of length dt on cells of size h (see above).
  void set_pressure_unit(double dt, double h) {
    pressure_unit = stiffest / h;
    if (dt > 0 && mobility > 0)
      pressure_unit = std::min(pressure_unit, std::sqrt(stiffest / (dt * mobility)));
  }

  /// The weight's share at the step's end.
  void set_gravity_share(double share) { gravity_head = share * full_gravity_head; }

  /// Per material: the pressure projection's tau.
  std::vector<double> projection() const {
    std::vector<double> tau;
    for (const PoreFlow& f : flow)
      tau.push_back(f.projection);
    return tau;
  }

  /// The case's consolidation, or none for a case without one; h the cell size.
  static std::optional<Consolidation> of(const CaseSpec& spec, double h) {
    if (!spec.consolidates())
      return std::nullopt;
    Consolidation c;
    for (const MaterialSpec& m : spec.materials) {
      const auto lame = LameParameters::from_young_poisson(m.youngs_modulus, m.poisson_ratio);
      const double alpha = m.flow->biot_coefficient;
      c.flow.push_back({alpha, m.flow->inverse_biot_modulus,
                        m.flow->permeability / spec.water->unit_weight,
                        spec.solver.pressure_projection * alpha * alpha / (2 * lame.mu)});
      c.stiffest = std::max(c.stiffest, lame.p_wave_modulus());
      c.mobility = std::max(c.mobility, c.flow.back().mobility);
    }
    const double g = spec.gravity.norm();
    if (!spec.water->phreatic.empty() && g > 0)
      c.full_gravity_head = c.gravity_head = spec.water->unit_weight / g * head<Dim>(spec.gravity);
    c.set_pressure_unit(0, h);
    return c;
  }
};

/// One point's terms of the mass balance and their blocks, for a stencil of kNodes nodes.
template <int Dim, bool Axisymmetric, int kNodes> struct BiotPoint {
  using Weights = Eigen::Matrix<double, 1, kNodes>;
  using Grads = Eigen::Matrix<double, Dim, kNodes>;

  const Weights& weights; ///< N_j
  const Grads& grads;     ///< grad N_j at the step's start
  const Weights& hoop;    ///< N_j / r_n (axisymmetry)
  Mat3 dF;                ///< the trial step gradient
  const PoreFlow& flow;
  double volume_n = 0;   ///< V_n
  double dt = 0;         ///< the step's length
  double s = 1;          ///< the pressure unit
  double increment = 0;  ///< dp_p
  Vec<Dim> gradient;     ///< grad p at the step's end
  Vec<Dim> gravity_head; ///< h

  /// r_i for each node of the stencil.
  Weights residual() const {
    const double volume = flow.alpha * (dF.determinant() - 1.0) + flow.storage * increment;
    const Vec<Dim> drive = dt * flow.mobility * (gradient - gravity_head);
    return s * volume_n * (volume * weights + drive.transpose() * grads);
  }

  /// K_pu += d r / du (s V_n alpha N_i dJ/du_j); K_up += d(balance)/dp = -K_pu^T (the
  /// excess pressure's force -alpha p V grad N_i, V = J V_n, on the current configuration:
  /// d/dp_j = -s alpha N_j V_n dJ/du_i); K_pp += d r / dp (s^2 V_n (N_i N_j / M
  /// + dt k/gamma_w grad N_i . grad N_j)).
  template <class Up, class Pu, class Pp> void add_blocks(Up& K_up, Pu& K_pu, Pp& K_pp) const {
    const Eigen::Matrix<double, 1, Dim* kNodes> dJ =
        volume_change_gradient<Dim, Axisymmetric, kNodes>(grads, hoop, dF);
    for (int i = 0; i < kNodes; ++i) {
      const double c = s * flow.alpha * volume_n * weights[i];
      K_pu.row(i) += c * dJ;
      K_up.col(i) -= c * dJ.transpose();
    }
    K_pp.noalias() += (s * s * volume_n) * (flow.storage * weights.transpose() * weights +
                                            dt * flow.mobility * grads.transpose() * grads);
  }
};

} // namespace talus
