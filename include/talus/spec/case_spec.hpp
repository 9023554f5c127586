#pragma once
// The validated, typed content of a case file. The reader (case_reader.hpp) fills it; nothing
// downstream looks at YAML again. Every field documents its unit and default; the same text
// lives in docs/case-format.md.
#include "talus/core/errors.hpp"
#include "talus/core/types.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace talus {

/// explicit: dynamic, central-difference-like MPM step under a CFL limit.
/// implicit_quasistatic: equilibrium at each load step by Newton's method (pseudo-time t in
/// [0, end_time] scales every load by t / end_time).
/// implicit_dynamic: Newmark (beta = 1/4, gamma = 1/2) on the grid, Newton at each step,
/// loads constant in time like the explicit analysis.
enum class AnalysisType { Explicit, ImplicitQuasistatic, ImplicitDynamic };
/// What a 2D case stands for: a slice of a long body (plane strain, F33 = 1) or a meridian
/// plane of a body of revolution about x = 0 (axisymmetry: x = r, y = z, F33 = r / R, volumes
/// and masses per radian). A 3D case is neither.
enum class Geometry { PlaneStrain, Axisymmetric };
/// linear hats; uGIMP; cpGIMP (domains follow the stretch); quadratic and cubic B-splines;
/// CPDI (the deformed voxel as the domain).
enum class ShapeFunction { Linear, Gimp, CpGimp, BSpline2, BSpline3, Cpdi };
enum class UpdateScheme { USL, USF, MUSL };
/// Particle-grid velocity transfer: FLIP/PIC blend, or APIC (Jiang et al. 2015), which carries
/// an affine velocity per particle so affine fields such as a rigid spin transfer exactly.
enum class TransferScheme { Flip, Apic };
/// How `talus fos` searches: independent trials from scratch, bisected, or one run that loads
/// the case and then lowers the strength step by step from the loaded state.
enum class StrengthReductionMode { Trials, Incremental };
/// Which flow rule the reduced materials of a strength reduction keep: the case's dilation
/// angle, or Davis's (1968) associated equivalent of the reduced strength (procedure B of
/// Tschuchnigg, Schweiger & Sloan 2015), for psi < phi.
enum class StrengthReductionFlow { AsGiven, Davis };
enum class MaterialModel {
  LinearElastic,
  NeoHookean,
  Hencky,
  VonMises,
  Tresca,
  MohrCoulomb,
  DruckerPrager
};

inline bool is_plastic(MaterialModel m) {
  return m == MaterialModel::VonMises || m == MaterialModel::Tresca ||
         m == MaterialModel::MohrCoulomb || m == MaterialModel::DruckerPrager;
}

/// The plausibility checks of a case (talus/io/plausibility.hpp): each warns about a magnitude
/// far from what soils and rocks have, and `silence_warnings` names the ones a case accepts.
enum class PlausibilityCheck {
  Density,
  YoungsModulus,
  Strength,
  FrictionAngle,
  Load,
  Gravity,
  Displacement,
  Permeability,
  ConsolidationStep
};

/// Softening of c and phi with accumulated plastic shear strain (mohr_coulomb, drucker_prager).
struct ResidualStrengthSpec {
  double cohesion = 0;       ///< Pa, >= 0
  double friction_angle = 0; ///< degrees
  double plastic_strain = 0; ///< kappa at which the residual strength is reached, > 0
};
/// rectangle (2D) / box (3D): min, max; disc / sphere: centre, radius; polygon (2D) / prism
/// (3D: the polygon in x-y extruded from z_min to z_max); cylinder (3D): axis ends, radius.
enum class BodyShape { Rectangle, Disc, Polygon, Cylinder };
/// Platen: a rigid, frictionless plate on the face; the face's nodes share one normal
/// displacement, which the loads on them push (docs/case-format.md, boundaries).
enum class FaceCondition { Free, Fixed, Roller, Platen };

/// The faces of the grid (and of a box body, for tractions), in the order of the axes: face
/// 2 d is the lower one along axis d, 2 d + 1 the upper one. A 2D case has the first four.
enum Face : int { kXMin = 0, kXMax = 1, kYMin = 2, kYMax = 3, kZMin = 4, kZMax = 5 };
inline constexpr int kMaxFaces = 6;
constexpr int face_count(int dimension) {
  return 2 * dimension;
}
constexpr int face_axis(int face) {
  return face / 2;
}
constexpr bool face_is_upper(int face) {
  return face % 2 == 1;
}
/// "x_min", ..., "z_max".
const char* face_name(int face);

// Points and vectors of a case have three components; a 2D case leaves z at 0 (the reader
// refuses a third component there), so one CaseSpec serves every dimension and the solvers
// take the first Dim components.
struct GridSpec {
  int dimension = 2;          ///< the case's (CaseSpec::dimension)
  Vec3 origin{0.0, 0.0, 0.0}; ///< m, lower corner
  Vec3 extent{1.0, 1.0, 0.0}; ///< m, size along each axis (required)
  double cell_size = 0; ///< m, square (cubic) cells (required); extent a whole number of cells
  SourceLocation where;
};

/// How pore water flows through a material and couples to its skeleton (Biot consolidation;
/// docs/case-format.md, materials): Darcy's q = -k grad h, the skeleton's volume change
/// alpha div u, and the storage 1/M. A material with one makes the case a consolidation case.
struct PoreFlowSpec {
  double permeability = 0;         ///< k, m/s (the hydraulic conductivity), > 0
  double biot_coefficient = 1;     ///< alpha, in (0, 1]
  double inverse_biot_modulus = 0; ///< 1/M, 1/Pa (0: incompressible fluid and grains)
};

struct MaterialSpec {
  std::string name;                                   ///< required, unique
  MaterialModel model = MaterialModel::LinearElastic; ///< required
  double density = 0;        ///< kg/m^3, > 0 (required; or unit_weight / |g| when that is given)
  double youngs_modulus = 0; ///< Pa, > 0 (required)
  double poisson_ratio = 0;  ///< -, in (-1, 0.5) (required)
  // --- elasto-plastic models (docs/case-format.md, materials) ---
  bool small_strain = false;    ///< kinematics: small_strain (else finite_strain, Hencky)
  double yield_stress = 0;      ///< von_mises, Pa
  double hardening_modulus = 0; ///< von_mises, Pa (0: perfectly plastic)
  double cohesion = 0;          ///< tresca, mohr_coulomb, drucker_prager, Pa
  double friction_angle = 0;    ///< mohr_coulomb, drucker_prager, degrees
  double dilation_angle = 0;    ///< mohr_coulomb, drucker_prager, degrees (default 0)
  std::optional<ResidualStrengthSpec> residual; ///< softening; none: perfectly plastic
  /// kg/m^3, of the soil below the phreatic surface (saturated_density, or
  /// saturated_unit_weight / |g|); none: `density` everywhere. Only with a water section.
  std::optional<double> saturated_density;
  std::optional<PoreFlowSpec> flow; ///< none: the material does not consolidate
  SourceLocation where;
};

/// Pore water at rest (docs/case-format.md, water): a phreatic surface, hydrostatic pore
/// pressure u = gamma_w (y_w(x) - y) below it and none above (no suction), y vertical.
struct WaterSpec {
  double unit_weight = 9810; ///< gamma_w, N/m^3
  /// The phreatic surface: y_w at each listed x (a polyline, ascending x, constant beyond its
  /// ends; in 3D extruded along z), or one point's y for a level surface.
  /// Empty: no water table (a consolidation case's excess pore pressure only; u = 0 at rest).
  std::vector<std::array<double, 2>> phreatic;
  /// Per grid face (x_min, x_max, y_min, ...): whether it is drained, its pore pressure held at
  /// the water table's (consolidation; the body's free surface is always drained).
  std::array<bool, 6> drained{};
  SourceLocation where;
};

/// Material-point splitting of a body (Andersen 2013; docs/case-format.md, bodies.split).
/// F^split = F F0^-1 is the deformation since the point was made (F0 its F then); the point
/// splits in two when F^split_11 or F^split_22 leaves [beta, alpha] or |F^split_12| or
/// |F^split_21| exceeds gamma.
struct SplitSpec {
  double alpha = 2.0;      ///< stretch limit, > 1
  double beta = 0.5;       ///< compression limit, in (0, 1)
  double gamma = 1.0;      ///< shear limit, > 0
  int max_generations = 3; ///< splits in a point's ancestry, 0 to 30
  double min_size = 0.0;   ///< m, no child whose deformed edge across the cut is shorter
};

struct BodySpec {
  std::string name; ///< required, unique
  BodyShape shape = BodyShape::Rectangle;
  std::string material;    ///< name of a MaterialSpec (required)
  int material_index = -1; ///< resolved by the reader
  // rectangle
  Vec3 min{0, 0, 0}, max{0, 0, 0}; ///< m
  // disc
  Vec3 centre{0, 0, 0}; ///< m
  double radius = 0;    ///< m, > 0
  // polygon (counter-clockwise or clockwise, simple); prism: the section, and its z range
  std::vector<Vec2> vertices;  ///< m, at least 3
  double z_min = 0, z_max = 0; ///< m, prism only (0 in 2D)
  // cylinder
  Vec3 axis_start{0, 0, 0}, axis_end{0, 0, 0}; ///< m, the ends of the axis
  int particles_per_cell = 2;                  ///< per direction, >= 1 (default 2)
  Vec3 velocity{0, 0, 0};                      ///< m/s, initial translational velocity (default 0)
  /// Per component: an expression of the initial position (x, y) that replaces velocity[d],
  /// e.g. "0.01 * sin(pi / 50 * x)"; empty when the component is a number.
  std::array<std::string, 3> velocity_expression;
  std::array<SourceLocation, 3> velocity_where; ///< of each velocity component's value
  /// Initial stress (plastic models only; docs/case-format.md, bodies.initial_stress).
  struct InitialStress {
    enum class Kind { Geostatic, Uniform } kind = Kind::Geostatic;
    /// geostatic: sigma_yy = -rho |g| (surface - y), sigma_xx = sigma_zz = k0 sigma_yy
    double surface = 0;       ///< m, y of the free surface (default: the body's top)
    std::optional<double> k0; ///< default nu / (1 - nu); `k0: jaky` gives 1 - sin(phi)
    /// uniform: the Cauchy stress, Pa (2D files give sigma_xx, sigma_yy, sigma_xy, sigma_zz)
    Mat3 stress = Mat3::Zero();
    /// The value the stress follows from (uniform: stress; geostatic: k0, or the section), for
    /// a stress the material refuses (outside its yield surface).
    SourceLocation where;
  };
  std::optional<InitialStress> initial_stress;
  double angular_velocity = 0; ///< rad/s, initial rigid spin about the body's centroid (default 0)
  std::optional<SplitSpec> split; ///< absent: the body's points never split
  /// Where the points sit on their lattice (docs/case-format.md, bodies.placement): a shift of
  /// the whole lattice and a random, seeded displacement of each point, both in units of the
  /// lattice spacing h / particles_per_cell.
  struct Placement {
    Vec3 offset{0, 0, 0}; ///< each component in (-0.5, 0.5)
    double jitter = 0;    ///< [0, 0.5): each point moves by up to jitter x spacing per axis
    unsigned seed = 1;    ///< of the jitter's random sequence (same seed, same points)
  };
  Placement placement;
  /// Local refinement (written by `talus adapt`): the grid cells whose centre lies in one of
  /// `boxes` get `particles_per_cell` points per direction instead of the body's.
  struct Refine {
    struct Box {
      Vec3 min{0, 0, 0}, max{0, 0, 0}; ///< m (2D files: [x_min, y_min, x_max, y_max])
    };
    int particles_per_cell = 4;
    std::vector<Box> boxes;
  };
  std::optional<Refine> refine;
  SourceLocation where;
};

/// The condition on each grid face, indexed by Face (default free).
struct BoundarySpec {
  std::array<FaceCondition, kMaxFaces> face{};
  FaceCondition operator[](int f) const { return face[static_cast<std::size_t>(f)]; }
  FaceCondition& operator[](int f) { return face[static_cast<std::size_t>(f)]; }
};

struct PointLoadSpec {
  std::string name;    ///< optional label (default "load<i>")
  Vec3 point{0, 0, 0}; ///< m, applied to the particle nearest to this point at t = 0
  Vec3 force{0, 0, 0}; ///< N (per unit thickness in 2D)
  SourceLocation where;
};

struct TractionSpec {
  std::string body; ///< rectangle body name
  int body_index = -1;
  int side = kYMax;       ///< the body's face (Face)
  Vec3 traction{0, 0, 0}; ///< Pa (N/m^2 on the side)
  /// Implicit analyses: applied in full from the first step instead of following the load
  /// factor (e.g. the confining pressure that balances an initial stress).
  bool constant = false;
  SourceLocation where;
};

/// Grid nodes inside a box follow a prescribed displacement (implicit analyses): each given
/// component reaches its value at end_time, ramped linearly in t / end_time; a component left
/// out (null) stays free. The support force they need is reported as a reaction.
struct PrescribedSpec {
  std::string name;                                  ///< required, unique; names the reaction
  Vec3 min{0, 0, 0}, max{0, 0, 0};                   ///< m, the box (inclusive) of grid nodes
  std::array<std::optional<double>, 3> displacement; ///< m, at end_time
  SourceLocation where;
};

struct TimeSpec {
  double end_time = 0;        ///< s, > 0 (required)
  std::optional<double> dt;   ///< s, > 0: fixed step; exactly one of dt and cfl
  std::optional<double> cfl;  ///< -, in (0, 1): dt = cfl * h / max(c_p + |v|)
  Index max_steps = 10000000; ///< safety cap (default 1e7)
  /// Implicit: smallest load step the adaptive stepping may cut back to (default dt / 1024).
  std::optional<double> min_dt;
  /// min_dt or its default (an implicit analysis has dt).
  double smallest_step() const { return min_dt.value_or(dt.value_or(0.0) / 1024.0); }
};

/// PlasticStrain: the accumulated equivalent plastic shear strain of the elasto-plastic models
/// (only valid when the case has one).
enum class OutputField {
  Velocity,
  Mass,
  Volume,
  DeformationGradient,
  Stress,
  Material,
  PlasticStrain,
  ReferencePosition, ///< x0, the position in the reference configuration (displacement x - x0)
  PorePressure,      ///< u, the pore pressure the total stress holds (a case with water)
  EffectiveStress    ///< sigma' = sigma + u I (a case with water)
};

/// output.checkpoint: when a run saves the state it can resume from (talus run --resume);
/// also at every stage end and on SIGINT/SIGTERM. The last two checkpoints are kept.
struct CheckpointSpec {
  std::optional<Index> every_steps;    ///< after every N completed steps
  std::optional<double> every_seconds; ///< s of wall time since the last checkpoint
};

struct OutputSpec {
  std::optional<CheckpointSpec> checkpoint; ///< none: no checkpoints
  std::optional<Index> every_steps; ///< write a frame every N steps; default: 20 frames per run
  std::optional<double> every_time; ///< s, write a frame every interval
  /// Default: the six kinematic and stress fields, plus plastic_strain when any material is
  /// elasto-plastic and pore_pressure and effective_stress when the case has water (the reader
  /// adds them).
  std::vector<OutputField> fields{OutputField::Velocity, OutputField::Mass,
                                  OutputField::Volume,   OutputField::DeformationGradient,
                                  OutputField::Stress,   OutputField::Material};
  /// Grid-node stress and smoothed particle stress (Andersen 2013) on every frame (default off).
  bool stress_recovery = false;
  /// Deformed voxels and colour patterns on every frame (default off).
  bool voxels = false;
  std::optional<double> pattern_size; ///< m, side of the pattern squares (default: cell size)
};

struct ProbeSpec {
  std::string name;              ///< required, unique; used in timeseries.csv column names
  std::optional<Index> particle; ///< particle index, or
  std::optional<Vec3> point;     ///< m, nearest particle at t = 0
  SourceLocation where;
  SourceLocation particle_where; ///< of the particle index
};

struct SolverSpec {
  ShapeFunction shape = ShapeFunction::Gimp;      ///< default gimp
  UpdateScheme scheme = UpdateScheme::MUSL;       ///< default musl
  TransferScheme transfer = TransferScheme::Flip; ///< default flip
  /// With transfer flip: FLIP fraction in [0, 1] of the particle velocity update
  /// (1 = FLIP, 0 = PIC). Ignored by apic.
  double flip = 1.0;
  // --- implicit analyses ---
  /// cholmod | umfpack | klu | eigen_cg | eigen_bicgstab | trilinos_cg | trilinos_gmres; empty:
  /// chosen by the solver (cholmod, or umfpack when a material's tangent is nonsymmetric)
  std::string linear_solver;
  double newton_tolerance = 1e-8; ///< max |R| <= tolerance * (largest external force scale)
  int max_newton_iterations = 20;
  /// A converged step with at most this many Newton iterations is easy; after two easy steps
  /// in a row a cut-back step doubles back towards time.dt.
  int easy_newton_iterations = 4;
  /// Ghost-penalty factor gamma (dimensionless, times Young's modulus) on the faces of the
  /// boundary cells; 0 switches the stabilisation off. See ghost_penalty.hpp.
  double ghost_penalty = 1e-3;
  /// F-bar: average each step's volume change over the points of a cell (f_bar.hpp), the
  /// remedy for volumetric locking (nu -> 1/2, isochoric plastic flow). Implicit only; makes
  /// the tangent nonsymmetric.
  bool f_bar = false;
  /// Plane strain only: F-bar spreads a step's volume change over the out-of-plane axis too,
  /// dF_bar = (J_bar / j)^(1/3) dF with dF_bar33 != 1, as a 3D slab between z rollers does and
  /// as Hughes' B-bar does in plane strain. Off (the default), F-bar scales the in-plane block
  /// by (J_bar / j)^(1/2) and keeps dF33 = 1 (de Souza Neto et al. 1996), which relieves
  /// isochoric plastic flow in plane strain better (docs/case-format.md).
  bool f_bar_out_of_plane = false;
  /// Consolidation: the factor on the pressure projection's tau = alpha^2 / (2 G)
  /// (pressure_projection.hpp), the stabilisation of equal-order u and p near the undrained
  /// limit; 0 switches it off.
  double pressure_projection = 1;
};

/// `talus fos`: the strength-reduction search for the factor of safety (docs/case-format.md,
/// strength_reduction). Each trial factor F loads the case with c / F and tan(phi) / F from
/// scratch; the search brackets the smallest F at which the loading fails and bisects.
struct StrengthReductionSpec {
  double lower = 1.0;      ///< -, first trial factor; expected to stand (default 1)
  double upper = 2.0;      ///< -, second trial factor; raised (x 1.5) while it still stands
  double tolerance = 0.01; ///< -, stop when the bracket is at most this wide
  int max_trials = 16;     ///< trials before the search gives up (no hang), >= 2
  std::string probe;       ///< probe whose displacement is the crest displacement (required)
  /// -, in (0, 1): a trial fails once the slope's current stiffness under its own weight
  /// (Bergan's parameter: the first load step's compliance over the current one) falls below
  /// this: a mechanism has formed (docs/case-format.md#strength_reduction).
  double min_stiffness = 0.1;
  /// m; a trial whose converged crest displacement exceeds this also counts as failed (a
  /// serviceability limit). None: only the stiffness criterion decides.
  std::optional<double> displacement_limit;
  StrengthReductionMode mode = StrengthReductionMode::Trials;
  /// -, incremental mode: the smallest change of F a reduction step may be cut back to (the
  /// ramps' min_dt); none: tolerance / 64.
  std::optional<double> min_step;
  /// A staged case (incremental mode only): the stages (indices into `stages`, ascending) at
  /// whose end a search starts from the state the history left (undrained in consolidation);
  /// the factor of safety against time (run_factor_of_safety, strength_reduction.cpp).
  std::vector<std::size_t> after_stages;
  SourceLocation where;

  double smallest_step() const { return min_step.value_or(tolerance / 64.0); }
};

/// A stage ends early, "at rest", once the kinetic energy has stayed at or below
/// `kinetic_energy_ratio` times the largest kinetic energy of the stage for `duration` seconds
/// (a slide that has stopped; elastic ringing far below the slide's energy does not count).
struct RestCriterion {
  double kinetic_energy_ratio = 1e-3; ///< -, in (0, 1)
  double duration = 1.0;              ///< s, > 0
};

/// One stage of a staged analysis (`stages:`): the state (positions, stress, F, plastic
/// history) carries over from the stage before; the analysis, time stepping and strength may
/// change. Loads reach their full value in the first stage and keep it afterwards.
struct StageSpec {
  std::string name;
  AnalysisType analysis = AnalysisType::ImplicitQuasistatic;
  TimeSpec time;
  /// Strength factor F at the end of the stage: c / F, tan(phi) / F (reduce_strength). A
  /// quasi-static stage moves it linearly from the previous stage's factor (1 before the
  /// first); a dynamic stage applies it at its first step. Absent: the previous stage's.
  std::optional<double> strength_factor;
  std::optional<double> wall_time_limit; ///< s; the run stops (interrupted) past it
  std::optional<RestCriterion> at_rest;  ///< dynamic stages: end once the body is at rest
  /// The water table at the end of the stage: a quasi-static stage moves the pore pressure
  /// linearly from the previous stage's table (the case's before the first), a dynamic one
  /// sets it at its first step. Absent: the previous stage's.
  std::optional<WaterSpec> water;
  /// Consolidation: no flow through the stage; the pore water carries the skeleton's volume
  /// change where it is (a failure faster than the water drains, the strength-reduction ramps
  /// after a coupled history). Set by `talus fos`, not read from a case.
  bool undrained = false;
  SourceLocation where;
};

struct CaseSpec {
  std::string name;                   ///< required; default output dir results/<name>
  std::string source_file;            ///< path the case was read from
  std::string source_text;            ///< verbatim case file text (embedded in run.h5)
  std::vector<std::string> overrides; ///< the --set strings applied, in order
  AnalysisType analysis = AnalysisType::Explicit;
  int dimension = 2;                         ///< 2 (plane strain or axisymmetric) or 3
  Geometry geometry = Geometry::PlaneStrain; ///< 2D only (default plane_strain)
  GridSpec grid;
  std::vector<MaterialSpec> materials;
  std::vector<BodySpec> bodies;
  Vec3 gravity{0, 0, 0}; ///< m/s^2 (default 0)
  BoundarySpec boundaries;
  std::vector<PointLoadSpec> point_loads;
  std::vector<TractionSpec> tractions;
  std::vector<PrescribedSpec> prescribed;
  TimeSpec time;
  OutputSpec output;
  std::vector<ProbeSpec> probes;
  SolverSpec solver;
  std::optional<WaterSpec> water; ///< none: a dry case (every stress is effective)
  std::optional<StrengthReductionSpec> strength_reduction; ///< `talus fos` only
  /// How every strength factor weakens the materials (strength_reduction.flow_rule); kept by
  /// the incremental search's staged case, which has no strength_reduction section.
  StrengthReductionFlow strength_flow_rule = StrengthReductionFlow::AsGiven;
  /// Staged analysis; empty: one stage of `analysis` over `time`. When given, `analysis` and
  /// `time` above are the first stage's.
  std::vector<StageSpec> stages;
  /// The plausibility warnings this case accepts (`silence_warnings`).
  std::vector<PlausibilityCheck> silenced_warnings;
  /// Where each value of a map in the case file sat, by key path ("materials[0].cohesion"), for
  /// messages about the case after it was read.
  std::map<std::string, SourceLocation> locations;

  /// Where the value at `key` sat, or `fallback` (a value given outside a map, or a default).
  const SourceLocation& location_of(const std::string& key, const SourceLocation& fallback) const {
    const auto found = locations.find(key);
    return found != locations.end() ? found->second : fallback;
  }

  /// Whether a body starts from a geostatic stress, which balances the full weight: the weight
  /// (and its pore water) then acts in full from the first load step instead of growing.
  /// Whether the pore pressure is an unknown coupled to the skeleton (Biot consolidation): a
  /// material has a pore flow.
  bool consolidates() const {
    return water && std::any_of(materials.begin(), materials.end(),
                                [](const MaterialSpec& m) { return m.flow.has_value(); });
  }

  bool starts_geostatic() const {
    return std::any_of(bodies.begin(), bodies.end(), [](const BodySpec& b) {
      return b.initial_stress && b.initial_stress->kind == BodySpec::InitialStress::Kind::Geostatic;
    });
  }
};

} // namespace talus
