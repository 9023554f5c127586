#include "talus/verify/verification.hpp"

#include "cases.hpp"
#include "report.hpp"
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/parallel/communicator.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fmt/format.h>
#include <fmt/ranges.h>

namespace talus {

namespace fs = std::filesystem;

const std::vector<VerificationCase>& verification_cases() {
  static const std::vector<VerificationCase> cases = {verify_cases::vibrating_bar(),
                                                      verify_cases::vibrating_bar_implicit(),
                                                      verify_cases::vibrating_bar_3d(),
                                                      verify_cases::vibrating_bar_implicit_3d(),
                                                      verify_cases::vibrating_bar_shapes(),
                                                      verify_cases::colliding_discs(),
                                                      verify_cases::colliding_discs_shapes(),
                                                      verify_cases::rigid_translation(),
                                                      verify_cases::rigid_translation_3d(),
                                                      verify_cases::colliding_spheres(),
                                                      verify_cases::rigid_rotation(),
                                                      verify_cases::rigid_rotation_3d(),
                                                      verify_cases::cantilever(),
                                                      verify_cases::cantilever_shapes(),
                                                      verify_cases::cantilever_3d(),
                                                      verify_cases::cantilever_slab_3d(),
                                                      verify_cases::self_weight_column(),
                                                      verify_cases::self_weight_column_3d(),
                                                      verify_cases::submerged_column(),
                                                      verify_cases::terzaghi(),
                                                      verify_cases::infinite_slope_seepage(),
                                                      verify_cases::mandel(),
                                                      verify_cases::column_large_compression(),
                                                      verify_cases::grashof(),
                                                      verify_cases::strip_footing(),
                                                      verify_cases::strip_footing_frictional(),
                                                      verify_cases::axisymmetric_cylinder(),
                                                      verify_cases::lame_cylinder(),
                                                      verify_cases::breathing_cylinder(),
                                                      verify_cases::circular_footing(),
                                                      verify_cases::slope_fos(),
                                                      verify_cases::slope_drawdown(),
                                                      verify_cases::embankment_consolidation(),
                                                      verify_cases::slope_fos_refinement(),
                                                      verify_cases::slope_fos_refinement_c5_phi30(),
                                                      verify_cases::slope_fos_refinement_steep(),
                                                      verify_cases::slope_fos_slab_3d(),
                                                      verify_cases::slope_3d_end_walls(),
                                                      verify_cases::single_element(),
                                                      verify_cases::single_element_3d(),
                                                      verify_cases::stability_explicit_cfl(),
                                                      verify_cases::stability_implicit_dt(),
                                                      verify_cases::stability_cell_crossing(),
                                                      verify_cases::stability_tiny_mass(),
                                                      verify_cases::stability_stiffness_contrast(),
                                                      verify_cases::stability_incompressibility(),
                                                      verify_cases::stability_rotation(),
                                                      verify_cases::stability_distortion(),
                                                      verify_cases::stability_perturbed(),
                                                      verify_cases::stability_recovery()};
  return cases;
}

fs::path verification_dir() {
  if (const char* dir = std::getenv("TALUS_DATA_DIR"))
    return fs::path(dir) / "verification";
  return fs::path(TALUS_SOURCE_DIR) / "verification";
}

CaseSpec load_verification_case(const VerificationContext& ctx,
                                const std::vector<std::string>& overrides) {
  return read_case_file(ctx.case_file.string(), overrides);
}

using verify_report::CaseOutcome;

namespace {

bool selected(const VerificationCase& vc, const VerifyOptions& options) {
  if (!options.only.empty())
    return std::find(options.only.begin(), options.only.end(), vc.name) != options.only.end();
  return std::find(vc.tiers.begin(), vc.tiers.end(), options.tier) != vc.tiers.end();
}

/// The selected cases that run distributed; a case named by --case that does not is refused.
std::vector<std::string> distributable_selection(const VerifyOptions& options) {
  std::vector<std::string> names, refused;
  for (const auto& vc : verification_cases())
    if (selected(vc, options))
      (vc.distributable ? names : refused).push_back(vc.name);
  if (!options.only.empty() && !refused.empty())
    throw InputError({"--case", 0, 0, ""},
                     fmt::format("{} do(es) not run distributed (not marked distributable)",
                                 fmt::join(refused, ", ")));
  if (names.empty())
    throw InputError({"--mpi", 0, 0, ""}, "no selected verification case runs distributed");
  return names;
}

/// `talus verify --mpi N`: this command again, under `mpirun -np N`, for the selected cases that
/// distribute; its exit code.
int verify_under_mpirun(const VerifyOptions& options) {
  const std::vector<std::string> names = distributable_selection(options);
  const std::string mpirun = mpirun_for_children();
  std::vector<std::string> args = {mpirun,
                                   "-np",
                                   std::to_string(options.mpi),
                                   "--oversubscribe",
                                   fs::read_symlink("/proc/self/exe").string(),
                                   "verify",
                                   "--tier",
                                   options.tier,
                                   "--out",
                                   options.out_dir.string()};
  if (options.threads > 0)
    args.insert(args.end(), {"--threads", std::to_string(options.threads)});
  for (const auto& name : names)
    args.insert(args.end(), {"--case", name});
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  fmt::print(stderr, "verify: {} case(s) under {} -np {}\n", names.size(), mpirun, options.mpi);
  pid_t pid = 0;
  if (::posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0)
    throw std::runtime_error("cannot start " + mpirun);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : kExitOther;
}

} // namespace

int run_verification(const VerifyOptions& options) {
  if (options.list) {
    for (const auto& vc : verification_cases())
      if (selected(vc, options))
        fmt::print("{}\n", vc.name);
    return kExitOk;
  }
  const Communicator& ranks = Communicator::world();
  if (options.mpi > 0 && !ranks.distributed())
    return verify_under_mpirun(options);
  // Under mpirun every rank runs every case (the runs are collective) and reads the results
  // rank 0 wrote; rank 0 alone prepares directories, reports and prints.
  if (ranks.distributed())
    distributable_selection(options);
  const fs::path out = options.out_dir;
  if (ranks.root())
    fs::create_directories(out);
  std::vector<CaseOutcome> outcomes;
  bool crashed = false;
  for (const auto& vc : verification_cases()) {
    if (!selected(vc, options) || (ranks.distributed() && !vc.distributable))
      continue;
    VerificationContext ctx;
    ctx.case_file = verification_dir() / ((vc.scene.empty() ? vc.name : vc.scene) + ".yaml");
    ctx.out_dir = out / vc.name;
    ctx.tier = options.tier;
    ctx.threads = options.threads;
    // The verification directory is the suite's own scratch space: each case starts clean.
    if (ranks.root()) {
      fs::remove_all(ctx.out_dir);
      fs::create_directories(ctx.out_dir);
      fmt::print(stderr, "verify: {} ...\n", vc.name);
    }
    ranks.barrier();
    const auto t0 = std::chrono::steady_clock::now();
    CaseOutcome outcome{&vc, {}, 0.0};
    try {
      outcome.checks = vc.run(ctx);
    } catch (const std::exception& e) {
      outcome.checks.push_back(
          holds_check("case ran to completion", false, std::string("error: ") + e.what()));
      crashed = true;
    }
    outcome.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    outcomes.push_back(std::move(outcome));
  }
  if (outcomes.empty())
    throw InputError({"--case", 0, 0, ""}, "no verification case matches the selection");
  const verify_report::Tally t = verify_report::tally(outcomes);
  if (!ranks.root())
    return crashed ? kExitOther : (t.all_held() ? kExitOk : kExitNumerical);
  verify_report::print_table(outcomes);
  verify_report::write_reports(out, options.tier, outcomes);
  fmt::print("\n{}: {} — report: {}\n", t.all_held() ? "PASSED" : "FAILED",
             verify_report::summary_line(t), (out / "report.md").string());
  if (crashed)
    return kExitOther;
  return t.all_held() ? kExitOk : kExitNumerical;
}

} // namespace talus
