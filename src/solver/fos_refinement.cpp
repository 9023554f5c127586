#include "talus/solver/fos_refinement.hpp"

#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/io/case_vocabulary.hpp"
#include "talus/post/python_script.hpp"
#include "talus/solver/run.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>

namespace talus {

namespace fs = std::filesystem;

namespace {

const char* const kRefinementEntries[] = {"refinement.csv", "refinement.json", "refinement.png"};

/// Each level's folder: h0.5, h0.25, ...
std::string level_name(double cell_size) {
  return fmt::format("h{:g}", cell_size);
}

/// The case at cell size h, searched over [lower, upper]: read again from its text with its
/// overrides, so that every check of the reader applies to the finer grid too.
CaseSpec level_case(const CaseSpec& spec, double cell_size, std::optional<double> lower,
                    std::optional<double> upper) {
  std::vector<std::string> overrides = spec.overrides;
  overrides.push_back(fmt::format("grid.cell_size={:.17g}", cell_size));
  if (lower)
    overrides.push_back(fmt::format("strength_reduction.lower={:.17g}", *lower));
  if (upper)
    overrides.push_back(fmt::format("strength_reduction.upper={:.17g}", *upper));
  return read_case_text(spec.source_text, spec.source_file, overrides);
}

/// The observed order and the extrapolation from the last three levels.
void judge_convergence(FosRefinement& r, double tolerance) {
  const std::size_t n = r.levels.size();
  if (n < 3) {
    r.message = fmt::format("{} level(s): an order needs three", n);
    return;
  }
  const double f1 = r.levels[n - 3].search.fos.value();
  const double f2 = r.levels[n - 2].search.fos.value();
  const double f3 = r.levels[n - 1].search.fos.value();
  const double d1 = f1 - f2, d2 = f2 - f3;
  if (std::abs(d1) <= tolerance && std::abs(d2) <= tolerance) {
    r.message = fmt::format("differences {:+.4f}, {:+.4f}: within the search tolerance {:g}", -d1,
                            -d2, tolerance);
    return;
  }
  if (d1 * d2 <= 0 || std::abs(d2) >= std::abs(d1)) {
    r.message = fmt::format("differences {:+.4f}, {:+.4f}: not converging monotonically", -d1, -d2);
    return;
  }
  r.observed_order = std::log2(d1 / d2);
  r.message = fmt::format("differences {:+.4f}, {:+.4f}: observed order {:.2f}", -d1, -d2,
                          *r.observed_order);
  if (*r.observed_order >= 0.5 && *r.observed_order <= 4) {
    r.extrapolated = f3 - d2 / (std::exp2(*r.observed_order) - 1);
    r.message += fmt::format(", extrapolated to h = 0: {:.4f}", *r.extrapolated);
  }
}

void write_outputs(const FosRefinement& r, const CaseSpec& spec, const fs::path& dir) {
  std::ofstream csv(dir / "refinement.csv");
  csv << "level,cell_size,factor_of_safety,lower,upper,bracketed,upper_undecided,trials,"
         "newton_iterations,wall_seconds,cpu_seconds\n";
  nlohmann::json j;
  j["case"] = spec.name;
  j["mode"] = choice_word(strength_reduction_mode_choices(), spec.strength_reduction->mode);
  j["levels"] = nlohmann::json::array();
  for (std::size_t k = 0; k < r.levels.size(); ++k) {
    const FosLevel& level = r.levels[k];
    const FosRunResult& s = level.search;
    csv << fmt::format("{},{:.10g},{:.10g},{:.10g},{:.10g},{},{},{},{},{:.4g},{:.4g}\n", k + 1,
                       level.cell_size, s.fos.value(), s.fos.lower, s.fos.upper,
                       s.fos.bracketed ? 1 : 0, s.fos.upper_undecided ? 1 : 0, s.fos.trials.size(),
                       s.newton_iterations, s.wall_seconds, s.cpu_seconds);
    j["levels"].push_back({{"cell_size", level.cell_size},
                           {"factor_of_safety", s.fos.value()},
                           {"bracket", {s.fos.lower, s.fos.upper}},
                           {"bracketed", s.fos.bracketed},
                           {"upper_undecided", s.fos.upper_undecided},
                           {"trials", s.fos.trials.size()},
                           {"newton_iterations", s.newton_iterations},
                           {"wall_seconds", s.wall_seconds},
                           {"cpu_seconds", s.cpu_seconds},
                           {"folder", level_name(level.cell_size)}});
  }
  j["observed_order"] = r.observed_order ? nlohmann::json(*r.observed_order) : nlohmann::json();
  j["extrapolated"] = r.extrapolated ? nlohmann::json(*r.extrapolated) : nlohmann::json();
  j["message"] = r.message;
  std::ofstream(dir / "refinement.json") << j.dump(2) << "\n";
  csv.close(); // the plot reads the file: flush it first
  run_python_script("plot_fos_refinement.py",
                    {(dir / "refinement.csv").string(), (dir / "refinement.png").string(),
                     spec.name, r.extrapolated ? fmt::format("{:.17g}", *r.extrapolated) : "",
                     r.message});
}

} // namespace

FosRefinement refine_factor_of_safety(const CaseSpec& spec, const FosOptions& options, int levels) {
  if (!spec.strength_reduction)
    throw InputError({spec.source_file, 0, 0, "strength_reduction"},
                     "talus fos needs a 'strength_reduction' section in the case");
  const fs::path dir =
      options.out_dir.empty() ? fs::path("results") / (spec.name + "-fos") : options.out_dir;
  const Communicator& ranks = Communicator::world();
  on_root(ranks, [&] {
    std::vector<const char*> owned(std::begin(kRefinementEntries), std::end(kRefinementEntries));
    std::vector<std::string> folders;
    for (int k = 0; k < levels; ++k)
      folders.push_back(level_name(spec.grid.cell_size / std::exp2(k)));
    for (const std::string& f : folders)
      owned.push_back(f.c_str());
    claim_output_directory(dir, options.force, owned);
    fs::create_directories(dir);
  });
  const double tolerance = spec.strength_reduction->tolerance;
  FosRefinement r;
  for (int k = 0; k < levels; ++k) {
    const double h = spec.grid.cell_size / std::exp2(k);
    FosOptions level = options;
    level.out_dir = dir / level_name(h);
    level.force = true; // the folder was claimed above
    std::optional<double> lower, upper;
    if (k > 0) {
      const FactorOfSafety& coarser = r.levels.back().search.fos;
      const double margin = 4 * tolerance;
      lower = std::max(coarser.lower - margin, 0.5 * coarser.value());
      upper = coarser.upper + margin;
      level.floor = 0.5 * coarser.value();
    }
    if (ranks.root())
      fmt::print("# level {} of {}: h = {:g}{}\n", k + 1, levels, h,
                 lower ? fmt::format(", F from {:.4g} to {:.4g}", *lower, *upper) : "");
    r.levels.push_back({h, run_factor_of_safety(level_case(spec, h, lower, upper), level)});
    const FosRunResult& s = r.levels.back().search;
    if (s.exit_code != kExitOk) {
      r.exit_code = s.exit_code;
      r.message =
          fmt::format("level {} (h = {:g}) ended without a factor: {}", k + 1, h, s.fos.message);
      break;
    }
  }
  if (r.exit_code == kExitOk)
    judge_convergence(r, tolerance);
  on_root(ranks, [&] { write_outputs(r, spec, dir); });
  return r;
}

} // namespace talus
