// Helpers the verification cases share (cases.hpp).
#include "cases.hpp"

#include <fmt/format.h>

namespace talus::verify_cases {

Mat3 final_point_stress(const VerificationContext& ctx, const std::string& run,
                        const std::vector<std::string>& overrides) {
  const auto dir = ctx.out_dir / run;
  run_quiet(load_verification_case(ctx, overrides), dir, ctx.threads);
  const ResultsReader results(dir / "run.h5");
  Index rows = 0, cols = 0;
  const auto s = results.read(results.frame_count() - 1, "stress", &rows, &cols);
  Mat3 sigma; // XDMF Tensor6 order: xx, xy, xz, yy, yz, zz
  sigma << s[0], s[1], s[2], s[1], s[3], s[4], s[2], s[4], s[5];
  return sigma;
}

PoreFrame read_pore_frame(const ResultsReader& results, Index frame) {
  Index rows = 0, dims = 0, cols = 0;
  PoreFrame f;
  f.x0 = results.read(frame, "reference_position", &rows, &dims);
  f.x = results.read(frame, "position", &rows, &dims);
  f.volume = results.read(frame, "volume", &rows, &cols);
  f.p = results.read(frame, "pore_pressure", &rows, &cols);
  f.dims = static_cast<std::size_t>(dims);
  return f;
}

RunResult run_quiet(const CaseSpec& spec, const std::filesystem::path& dir, int threads) {
  RunOptions options;
  options.out_dir = dir;
  options.force = true;
  options.threads = threads;
  options.progress = false;
  RunResult r = run_case(spec, options);
  if (r.exit_code != 0)
    throw NumericalError(fmt::format("run '{}' ended {}: {}", spec.name, r.status, r.message));
  return r;
}

FosRunResult bracketed_search(const VerificationContext& ctx, const CaseSpec& spec,
                              const std::string& name) {
  FosOptions options;
  options.out_dir = ctx.out_dir / name;
  options.force = true;
  options.threads = ctx.threads;
  FosRunResult r = run_factor_of_safety(spec, options);
  if (!r.fos.bracketed)
    throw NumericalError("strength reduction found no bracket: " + r.fos.message);
  return r;
}

} // namespace talus::verify_cases
