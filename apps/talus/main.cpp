// talus: the command-line front end. Sub-commands: run, fos, adapt, check, verify, bench, render,
// info.
// Exit codes: 0 success, 1 other error, 2 bad input, 3 numerical failure.
#include "talus/adapt/adapt.hpp"
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/io/case_vocabulary.hpp"
#include "talus/io/plausibility.hpp"
#include "talus/io/render.hpp"
#include "talus/linalg/linear_solver.hpp"
#include "talus/parallel/communicator.hpp"
#include "talus/scene/memory_estimate.hpp"
#include "talus/scene/run_time_estimate.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/fos_refinement.hpp"
#include "talus/solver/run.hpp"
#include "talus/solver/strength_reduction.hpp"
#include "talus/verify/bench.hpp"
#include "talus/verify/verification.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <omp.h>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

using namespace talus;

int print_info() {
  // Every enumerated word of a case file comes from the tables the reader validates against
  // (talus/io/case_vocabulary.hpp), so this list cannot go stale.
  const auto words = [](const std::vector<std::string>& names) {
    return fmt::format("{}", fmt::join(names, ", "));
  };
  fmt::print("talus {}\n", TALUS_VERSION);
  fmt::print("build type      {}\n", TALUS_BUILD_TYPE);
  fmt::print("dimension       2 (plane strain, axisymmetric), 3: every analysis\n");
  fmt::print("analyses        {}\n", words(choice_names(analysis_choices())));
  fmt::print("geometry (2D)   {}\n", words(choice_names(geometry_choices())));
  fmt::print("explicit scheme {}\n", words(choice_names(update_scheme_choices())));
  fmt::print("transfers       {} (solver.flip blends FLIP and PIC)\n",
             words(choice_names(transfer_scheme_choices())));
  fmt::print("shape functions {}\n", words(choice_names(shape_function_choices())));
  fmt::print("elastic models  {}\n", words(material_model_names(false)));
  fmt::print("plastic models  {}\n", words(material_model_names(true)));
  fmt::print("body shapes     {} (2D); {} (3D)\n", words(choice_names(body_shape_choices(2))),
             words(choice_names(body_shape_choices(3))));
  fmt::print("output fields   {}\n", words(choice_names(output_field_choices())));
  const char* wait_policy = std::getenv("OMP_WAIT_POLICY");
  const char* spin_count = std::getenv("GOMP_SPINCOUNT");
  fmt::print("OpenMP threads  {} available, waiting {}{}\n", omp_get_max_threads(),
             wait_policy != nullptr ? wait_policy : "(libgomp default: spinning)",
             spin_count != nullptr ? fmt::format(" after {} spins", spin_count) : "");
  fmt::print("linear solvers  {}\n", words(available_linear_solvers()));
  fmt::print("Newton driver   SUNDIALS KINSOL {}\n", TALUS_SUNDIALS_VERSION);
  fmt::print("results         HDF5 + XDMF (ParaView), CSV, JSON\n");
  fmt::print("data directory  {}\n", verification_dir().parent_path().string());
  return kExitOk;
}

/// Reads and validates the case and prints its plausibility warnings (once, from rank 0).
CaseSpec read_case(const std::string& case_file, const std::vector<std::string>& overrides) {
  CaseSpec spec = read_case_file(case_file, overrides);
  if (Communicator::world().root())
    for (const PlausibilityWarning& warning : plausibility_warnings(spec))
      fmt::print(stderr, "{}\n", describe(warning));
  return spec;
}

/// The estimate against what the machine has free right now: a case that fits in the machine
/// but not in its available memory may still run (the kernel reclaims caches), but the user
/// should know before a long run starts.
void warn_if_memory_is_short(const CaseSpec& spec) {
  const MemoryEstimate estimate = estimate_memory(spec);
  const MachineMemory machine = machine_memory();
  if (estimate.total_bytes > machine.available_bytes)
    fmt::print(stderr,
               "talus: warning: the case needs about {}, more than the {} available now "
               "(MemAvailable of /proc/meminfo)\n",
               format_bytes(estimate.total_bytes), format_bytes(machine.available_bytes));
}

/// talus check: reads and validates the case with its overrides and prints what it would
/// allocate; writes nothing. Exit 0, or 2 for bad input.
int check_command(const std::string& case_file, const std::vector<std::string>& overrides,
                  int threads) {
  const CaseSpec spec = read_case(case_file, overrides);
  const MemoryEstimate estimate = estimate_memory(spec);
  const MachineMemory machine = machine_memory();
  // The scene is the last place a case can be refused (a velocity expression that is NaN at a
  // point, a probe index beyond the points, an initial stress outside the yield surface). It is
  // built when that is quick; a case of gigabytes gets those checks at the start of its run.
  constexpr double kSceneCheckBytes = 1e9;
  if (estimate.total_bytes <= kSceneCheckBytes) {
    const Index points = spec.dimension == 3 ? build_scene<3>(spec).particles.size()
                                             : build_scene<2>(spec).particles.size();
    fmt::print("{}: valid case '{}', {} material points\n", case_file, spec.name, points);
  } else {
    fmt::print("{}: valid case '{}' (the scene, estimated above {}, is built and checked when "
               "the run starts)\n",
               case_file, spec.name, format_bytes(kSceneCheckBytes));
  }
  fmt::print("  grid      {:g} x {:g}{} cells of {:g} m, {:.6g} nodes\n", estimate.cells_x,
             estimate.cells_y,
             spec.dimension == 3 ? fmt::format(" x {:g}", estimate.cells_z) : std::string(),
             spec.grid.cell_size, estimate.nodes);
  for (std::size_t b = 0; b < spec.bodies.size(); ++b)
    fmt::print("  body      {}: about {:.6g} material points\n", spec.bodies[b].name,
               estimate.body_points[b]);
  fmt::print("  memory    about {}\n", estimate.describe());
  if (estimate.split_growth > 1)
    fmt::print("  splitting may multiply the points of a splitting body by up to {:g}\n",
               estimate.split_growth);
  fmt::print("  machine   {} in all ({}), {} available now\n", format_bytes(machine.total_bytes),
             machine.source, format_bytes(machine.available_bytes));
  const RunTimeEstimate time = estimate_run_time(spec, estimate, threads);
  if (time.unknowns > 0)
    fmt::print(
        "  solver    {} ({} tangent), about {:.4g} unknowns\n",
        to_string(implicit_linear_solver(spec.solver.linear_solver, time.symmetric, spec.dimension,
                                         static_cast<long long>(time.unknowns))),
        time.symmetric ? "symmetric" : "nonsymmetric", time.unknowns);
  fmt::print("  run time  {} on {} thread{}: a rough figure from costs measured on a 2-core "
             "machine, a factor of 3 either way (more where the soil yields)\n",
             time.describe(), threads, threads == 1 ? "" : "s");
  return kExitOk;
}

int run_command(const std::string& case_file, const std::vector<std::string>& overrides,
                RunOptions options) {
  const CaseSpec spec = read_case(case_file, overrides);
  warn_if_memory_is_short(spec);
  const RunResult r = run_case(spec, options);
  if (!Communicator::world().root())
    return r.exit_code;
  fmt::print("{}: {} — {} steps to t = {:g}, {} frames, {} particles, {:.2f} s -> {}\n", spec.name,
             r.status, r.steps, r.final_time, r.frames, r.particles, r.wall_seconds,
             r.out_dir.string());
  if (!r.message.empty())
    fmt::print(stderr, "talus: {}\n", r.message);
  return r.exit_code;
}

int fos_command(const std::string& case_file, const std::vector<std::string>& overrides,
                const FosOptions& options, int refine) {
  const CaseSpec spec = read_case(case_file, overrides);
  if (refine > 1) {
    const FosRefinement r = refine_factor_of_safety(spec, options, refine);
    if (!Communicator::world().root())
      return r.exit_code;
    for (const FosLevel& level : r.levels)
      fmt::print("{}: h = {:g}: factor of safety {:.4f} (bracket [{:.4f}, {:.4f}]{}), {} "
                 "Newton iterations, {:.1f} s\n",
                 spec.name, level.cell_size, level.search.fos.value(), level.search.fos.lower,
                 level.search.fos.upper,
                 level.search.fos.upper_undecided ? ", upper undecided" : "",
                 level.search.newton_iterations, level.search.wall_seconds);
    fmt::print("{}: {}\n", spec.name, r.message);
    return r.exit_code;
  }
  const FosRunResult r = run_factor_of_safety(spec, options);
  if (!Communicator::world().root())
    return r.exit_code;
  if (r.fos.bracketed)
    fmt::print("{}: factor of safety {:.4f} (bracket [{:.4f}, {:.4f}]), {} {}, {} Newton "
               "iterations, {:.2f} s ({:.2f} s of CPU) -> {}\n",
               spec.name, r.fos.value(), r.fos.lower, r.fos.upper, r.fos.trials.size(),
               spec.strength_reduction->mode == StrengthReductionMode::Incremental
                   ? "reduction steps in one run"
                   : "trials",
               r.newton_iterations, r.wall_seconds, r.cpu_seconds, r.out_dir.string());
  else
    fmt::print(stderr, "talus: {}: no factor of safety: {} -> {}\n", spec.name, r.fos.message,
               r.out_dir.string());
  return r.exit_code;
}

int adapt_command(const std::string& case_file, const std::vector<std::string>& overrides,
                  const AdaptOptions& options) {
  read_case(case_file, overrides);
  const AdaptReport report = adapt_case(case_file, overrides, options);
  fmt::print("marked {} of {} body cells; adapted case: {} --set ...\n{}", report.marked_cells,
             report.body_cells, case_file, adapt_table(report));
  return kExitOk;
}

} // namespace

namespace {

// OpenMP threads that finish a parallel loop spin-wait for the next one by default (libgomp:
// about 300 000 spins). Talus's parallel loops are short and separated by serial work (sparse
// factorisation, assembly), and on a 2-core machine that runs anything else the spinning
// threads take the cores the serial work needs. Measured side by side (2 cores, one other busy
// process): cantilever_large 1.21 -> 0.92 s, the verification tier under ctest -j2 77 -> 41 s,
// with OMP_WAIT_POLICY=passive. A thread that sleeps at once, though, must be woken by the
// kernel for each of an explicit step's dozen loops: a short spin (GOMP_SPINCOUNT = 10 000,
// about 0.1 ms) bridges the gaps between them and still sleeps through a factorisation
// (colliding discs at 40k points, 2 threads: 3.27 s sleeping at once, 2.38 s with the short
// spin, 2.30 s spinning without limit). libgomp reads both once, before main, so the binary
// re-executes itself with them set; what the user set is kept.
void run_with_short_openmp_waits(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr)
    return;
  if (setenv("OMP_WAIT_POLICY", "passive", 0) != 0 || setenv("GOMP_SPINCOUNT", "10000", 0) != 0)
    return;
  execv("/proc/self/exe", argv); // returns only on failure: carry on with the default policy
}

} // namespace

int main(int argc, char** argv) {
  run_with_short_openmp_waits(argv);
  // Under mpirun: MPI from here on; each rank then runs the same command on its share.
  Communicator::init_if_launched(argc, argv);
  const Communicator& ranks = Communicator::world();
  CLI::App app{"Talus: material point method for geomechanics"};
  app.require_subcommand(1);

  auto* run = app.add_subcommand("run", "Run a case file; results go to results/<case name>/");
  std::string case_file, out_dir;
  std::vector<std::string> overrides;
  bool force = false;
  int threads = 0;
  run->add_option("case", case_file, "Case file (YAML)")->required();
  run->add_option("--out", out_dir, "Output directory (default results/<case name>)");
  run->add_option("--set", overrides,
                  "Override a case key, e.g. --set solver.shape=linear (repeatable)");
  run->add_flag("--force", force, "Replace the results of an earlier run in the directory");
  run->add_option("--threads", threads, "OpenMP threads (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  std::string dump_tangent;
  run->add_option("--dump-tangent", dump_tangent,
                  "Implicit runs: write the last Newton tangent to this file (Matrix Market)");
  std::string resume_dir;
  bool accept_changes = false;
  auto* resume =
      run->add_option("--resume", resume_dir,
                      "Continue the run in this directory from its newest valid checkpoint "
                      "(output.checkpoint)");
  resume->excludes(run->get_option("--force"))->excludes(run->get_option("--out"));
  run->add_flag("--accept-changes", accept_changes,
                "With --resume: accept a case changed in end times, max_steps, wall-time "
                "limits or output")
      ->needs(resume);

  auto* fos = app.add_subcommand(
      "fos", "Factor of safety by strength reduction (c / F, tan phi / F, bisection on F); "
             "writes fos.csv, fos.png, fos.log and each trial's run");
  fos->add_option("case", case_file, "Case file (YAML) with a strength_reduction section")
      ->required();
  fos->add_option("--out", out_dir, "Output directory (default results/<case name>-fos)");
  fos->add_option("--set", overrides, "Override a case key (repeatable)");
  fos->add_flag("--force", force, "Replace the results of an earlier search in the directory");
  auto* fos_resume =
      fos->add_option("--resume", resume_dir,
                      "Continue the search in this directory: finished trials are kept, the "
                      "one cut short continues from its newest checkpoint");
  fos_resume->excludes(fos->get_option("--force"))->excludes(fos->get_option("--out"));
  fos->add_flag("--accept-changes", accept_changes,
                "With --resume: accept a case changed in end times, max_steps, wall-time "
                "limits or output")
      ->needs(fos_resume);
  fos->add_option("--threads", threads, "OpenMP threads (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  int refine = 1;
  fos->add_option("--refine", refine,
                  "Search on N grids, the case's cell size h, then h/2, ...: the factor against "
                  "h (refinement.csv, refinement.png) and its observed order")
      ->check(CLI::Range(1, 6))
      ->excludes(fos_resume);

  auto* adapt = app.add_subcommand(
      "adapt", "Coarse pre-run, finer points where it yielded or distorted, then the full run");
  AdaptOptions adapt_options;
  std::string adapt_out;
  adapt->add_option("case", case_file, "Case file (YAML)")->required();
  adapt->add_option("--out", adapt_out, "Output directory (default results/<case name>_adapt)");
  adapt->add_option("--set", overrides, "Override a case key (repeatable)");
  adapt->add_flag("--force", adapt_options.force, "Replace the results of an earlier adapt");
  adapt->add_option("--threads", adapt_options.threads, "OpenMP threads (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  adapt->add_option("--factor", adapt_options.factor,
                    "Points per direction in marked cells, times the body's (default 2)");
  adapt->add_option("--plastic-strain", adapt_options.plastic_strain,
                    "Mark where the accumulated plastic strain exceeds this (default 0.1)");
  adapt->add_option("--aspect-ratio", adapt_options.aspect_ratio,
                    "Mark where a voxel's aspect ratio exceeds this (default 2)");
  adapt->add_option("--buffer", adapt_options.buffer_cells,
                    "Cells marked around each marked cell (default 1)");
  adapt->add_flag("--benchmark", adapt_options.benchmark,
                  "Add a uniform fine run and compare coarse and adapted with it");

  auto* verify = app.add_subcommand("verify", "Run the verification suite and write a report");
  VerifyOptions verify_options;
  verify->add_option("--tier", verify_options.tier, "Which cases: fast, full or stability")
      ->check(CLI::IsMember({"fast", "full", "stability"}));
  verify->add_option("--out", verify_options.out_dir, "Report directory (default results/verify)");
  verify->add_option("--case", verify_options.only, "Run only this case (repeatable)");
  verify->add_flag("--list", verify_options.list, "Print the tier's case names and run none");
  verify->add_option("--threads", verify_options.threads, "OpenMP threads")
      ->check(CLI::NonNegativeNumber);
  verify
      ->add_option("--mpi", verify_options.mpi,
                   "Run the selected cases marked distributable under mpirun -np N")
      ->check(CLI::PositiveNumber);

  auto* bench = app.add_subcommand(
      "bench", "Work-precision sweep of a verification case: writes bench.csv and bench.png");
  BenchOptions bench_options;
  bench
      ->add_option("--case", bench_options.case_name,
                   "Verification case: " + fmt::format("{}", fmt::join(bench_cases(), ", ")))
      ->required();
  bench->add_option("--out", bench_options.out_dir,
                    "Output directory (default results/bench/<case>)");
  bench->add_option("--repeats", bench_options.repeats,
                    "Runs per configuration for the median (default 3, at least 3)");
  bench->add_flag("--quick", bench_options.quick, "Leave out the finest resolution");
  bench->add_option("--vs", bench_options.baseline,
                    "newton_cost, explicit_throughput: an older talus binary, run alternately with "
                    "this one");
  bench
      ->add_option("--threads", bench_options.threads,
                   "OpenMP threads of each run (default 1; 0: all cores)")
      ->check(CLI::NonNegativeNumber);

  auto* render_cmd = app.add_subcommand(
      "render", "Draw frames of a run as deformed voxels (or dots) coloured by a field: PNG");
  RenderOptions render_options;
  render_cmd->add_option("results", render_options.results, "run.h5 of a run")->required();
  render_cmd->add_option("--field", render_options.field,
                         "Particle field: stress, stress_smoothed, velocity, F, mass, ...");
  render_cmd->add_option("--component", render_options.component,
                         "Component: xx, xy, yy, zz, ... (tensors), x, y, z, magnitude "
                         "(vectors)");
  render_cmd->add_option("--frame", render_options.frame,
                         "Frame number, last (default) or all (a numbered sequence)");
  render_cmd->add_option("--pattern", render_options.pattern,
                         "Colour by a pattern instead: checker, stripes_horizontal, "
                         "stripes_vertical");
  render_cmd->add_option("--mode", render_options.mode,
                         "voxels or points (default: voxels when the run wrote them)");
  render_cmd->add_option("--slice", render_options.slice,
                         "3D runs: draw the voxels (or points) cut by a plane, e.g. z=0.5 "
                         "(also x=..., y=...)");
  render_cmd->add_option("--view", render_options.view,
                         "3D runs without --slice: outer faces seen from iso, x, y or z "
                         "(default: the slice z = const through the point that moved the most)");
  render_cmd->add_option("--clim", render_options.clim, "Colour range: LO HI")->expected(2);
  render_cmd->add_flag("--log", render_options.log, "Logarithmic colour scale");
  render_cmd
      ->add_option("--crop", render_options.crop, "Draw only X0 Y0 X1 Y1 of the picture's axes")
      ->expected(4);
  render_cmd->add_flag("--delta", render_options.delta, "Colour by the change since frame 0");
  render_cmd->add_option("-o,--output", render_options.output, "Output picture (.png)")->required();

  auto* check = app.add_subcommand(
      "check", "Read and validate a case (with its --set overrides) and print its memory "
               "estimate, linear solver and rough run time; writes nothing (exit 0, or 2 for "
               "bad input)");
  check->add_option("case", case_file, "Case file (YAML)")->required();
  check->add_option("--set", overrides, "Override a case key (repeatable)");
  check
      ->add_option("--threads", threads,
                   "Threads the run-time estimate assumes (default: all cores)")
      ->check(CLI::NonNegativeNumber);

  auto* info = app.add_subcommand("info", "Version, build options and available backends");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  }

  try {
    // Under mpirun the ranks share a run's points: only the commands that step a case run
    // there.
    if (ranks.distributed() && !*run && !*fos && !*verify)
      throw InputError({"mpirun", 0, 0, ""},
                       fmt::format("talus {} does not run under mpirun; start it without",
                                   app.get_subcommands().front()->get_name()));
    if (*run) {
      RunOptions options;
      options.out_dir = resume_dir.empty() ? out_dir : resume_dir;
      options.force = force;
      options.threads = threads;
      options.dump_tangent = dump_tangent;
      options.resume = !resume_dir.empty();
      options.accept_changes = accept_changes;
      return run_command(case_file, overrides, options);
    }
    if (*fos) {
      FosOptions options;
      options.out_dir = resume_dir.empty() ? out_dir : resume_dir;
      options.force = force;
      options.threads = threads;
      options.resume = !resume_dir.empty();
      options.accept_changes = accept_changes;
      return fos_command(case_file, overrides, options, refine);
    }
    if (*adapt) {
      adapt_options.out_dir = adapt_out;
      return adapt_command(case_file, overrides, adapt_options);
    }
    if (*verify)
      return run_verification(verify_options);
    if (*bench)
      return run_bench(bench_options);
    if (*render_cmd)
      return render(render_options);
    if (*check)
      return check_command(case_file, overrides, threads > 0 ? threads : omp_get_max_threads());
    if (*info)
      return print_info();
  } catch (const InputError& e) {
    // Bad input and numerical failures reach every rank of a distributed run together: rank 0
    // reports them.
    if (ranks.root())
      fmt::print(stderr, "talus: error: {}\n", e.what());
    return kExitBadInput;
  } catch (const NumericalError& e) {
    if (ranks.root())
      fmt::print(stderr, "talus: numerical failure: {}\n", e.what());
    return kExitNumerical;
  } catch (const std::exception& e) {
    // Anything else may have struck one rank alone, while the others wait for it.
    if (ranks.distributed()) {
      fmt::print(stderr, "talus: rank {}: {}\n", ranks.rank(), e.what());
      std::fflush(stderr);
      MPI_Abort(ranks.mpi(), kExitOther);
    }
    fmt::print(stderr, "talus: {}\n", e.what());
    return kExitOther;
  }
  return kExitOther;
}
