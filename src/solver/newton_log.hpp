#pragma once
// Internal to run_case: newton.log, one line per load-step attempt of the implicit stages
// (step, end time, step length, converged, iterations, then max|R|/scale at each iterate).
// One log for the run: the first stage creates it, later stages and resumed runs append; in a
// distributed run Newton is one over the ranks and rank 0 writes it.
#include "talus/solver/newton.hpp"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

namespace talus::run_detail {

class NewtonLog {
public:
  /// `writes`: this rank writes (the others write to /dev/null); `create`: a new log.
  NewtonLog(const std::filesystem::path& out_dir, bool writes, bool create)
      : file_(
            std::fopen(writes ? (out_dir / "newton.log").c_str() : "/dev/null", create ? "w" : "a"),
            std::fclose) {
    if (!file_)
      throw std::runtime_error("cannot create " + (out_dir / "newton.log").string());
    if (create)
      std::fprintf(file_.get(), "# step t_end dt converged iterations | max|R|/scale at each "
                                "iterate\n");
  }

  /// A staged run's stage header.
  void stage(std::size_t index, const std::string& name, double start_time) {
    std::fprintf(file_.get(), "# stage %zu '%s' from t = %.10g\n", index + 1, name.c_str(),
                 start_time);
  }

  /// One attempt of the step numbered `step` to `t_end`, with an abandoned first attempt's
  /// history in brackets.
  void attempt(Index step, double t_end, double dt, const NewtonReport& r) {
    std::FILE* f = file_.get();
    std::fprintf(f, "%lld %.10g %.6g %s %d |", static_cast<long long>(step), t_end, dt,
                 r.converged ? "yes" : "no", r.iterations);
    if (!r.abandoned_history.empty()) {
      std::fprintf(f, " [%s:", r.abandoned_line_search ? "line search" : "plain Newton");
      for (double v : r.abandoned_history)
        std::fprintf(f, " %.3e", v);
      std::fprintf(f, "; %s:]", r.abandoned_line_search ? "plain Newton" : "line search");
    }
    for (double v : r.residual_history)
      std::fprintf(f, " %.3e", v);
    std::fprintf(f, "%s%s\n", r.converged ? "" : "  ", r.message.c_str());
    std::fflush(f);
  }

private:
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
};

} // namespace talus::run_detail
