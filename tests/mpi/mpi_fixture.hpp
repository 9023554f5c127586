#pragma once
// What the distributed-run tests share: `mpirun -np N talus ...` beside `talus ...` in one work
// directory, and the comparison of the two results.
#include "../unit/cli_support.hpp"
#include "../unit/result_comparison.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <signal.h>
#include <thread>

namespace fs = std::filesystem;

namespace talus::test_support {

inline const fs::path kCases = fs::path(TALUS_SOURCE_DIR) / "cases";

/// `args` followed by `more`.
inline std::vector<std::string> appended(std::vector<std::string> args,
                                         const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

inline nlohmann::json summary_of(const fs::path& dir) {
  std::ifstream in(dir / "summary.json");
  return nlohmann::json::parse(in);
}

/// The processes `pid` started (mpirun's ranks).
inline std::vector<pid_t> children_of(pid_t pid) {
  std::vector<pid_t> out;
  for (const auto& task :
       fs::directory_iterator(fs::path("/proc") / std::to_string(pid) / "task")) {
    std::ifstream in(task.path() / "children");
    for (pid_t child = 0; in >> child;)
      out.push_back(child);
  }
  return out;
}

class Mpi : public Cli {
protected:
  void SetUp() override {
    Cli::SetUp();
    // CI runs as root, which OpenMPI refuses unless told; every rank shares the machine's
    // two cores (oversubscribed).
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    ::setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
  }

  /// `mpirun -np N talus ARGS` in the work directory.
  Outcome mpirun(int ranks, const std::vector<std::string>& args) {
    std::vector<std::string> all = {"-np", std::to_string(ranks), "--oversubscribe", TALUS_BINARY};
    all.insert(all.end(), args.begin(), args.end());
    Child child(all, work(), root_, TALUS_MPIEXEC);
    EXPECT_TRUE(child.started());
    return child.wait();
  }

  /// The case run serially into `serial` and on `ranks` ranks into `distributed`; both complete.
  void run_both(const fs::path& case_file, const std::vector<std::string>& sets, int ranks) {
    std::vector<std::string> args = {"run", case_file.string(), "--threads", "1"};
    for (const auto& s : sets) {
      args.push_back("--set");
      args.push_back(s);
    }
    const Outcome serial = talus(appended(args, {"--out", "serial"}));
    ASSERT_EQ(serial.exit_code, 0) << serial.describe();
    const Outcome distributed = mpirun(ranks, appended(args, {"--out", "distributed"}));
    ASSERT_EQ(distributed.exit_code, 0) << distributed.describe();
    const auto a = summary_of(work() / "serial"), b = summary_of(work() / "distributed");
    EXPECT_EQ(a.at("steps"), b.at("steps"));
    EXPECT_EQ(a.at("particles"), b.at("particles"));
    EXPECT_EQ(a.at("frames"), b.at("frames"));
  }

  /// `mpirun -np 2 talus ARGS` writing into `out`, and SIGTERM to its second rank once the
  /// run's timeseries.csv has `rows` lines (a scheduler signals a job's tasks; mpirun itself
  /// passes a signal on only after a delay). The run must end interrupted.
  void interrupt_one_rank(const std::vector<std::string>& args, const std::string& out, long rows) {
    const std::vector<std::string> launch =
        appended({"-np", "2", "--oversubscribe", TALUS_BINARY}, args);
    Child child(launch, work(), root_, TALUS_MPIEXEC);
    ASSERT_TRUE(child.started());
    const fs::path series = work() / out / "timeseries.csv";
    while (!fs::exists(series) ||
           std::count(std::istreambuf_iterator<char>(*std::make_unique<std::ifstream>(series)), {},
                      '\n') < rows) {
      if (const auto done = child.poll())
        FAIL() << "the run ended before the interrupt:\n" << done->describe();
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    const std::vector<pid_t> ranks = children_of(child.pid());
    ASSERT_EQ(ranks.size(), 2u);
    ::kill(ranks.back(), SIGTERM);
    const Outcome stopped = child.wait();
    ASSERT_EQ(summary_of(work() / out).at("status"), "interrupted") << stopped.describe();
  }

  /// The two results agree to `relative` of each field's and column's scale; a momentum that
  /// is conserved at zero is judged against the largest momentum of the motion, sqrt(2 M E_kin).
  void expect_agree(double relative, const std::string& other = "distributed") {
    const talus::CsvTable series = talus::read_csv(work() / "serial" / "timeseries.csv");
    const talus::ResultsReader reader(work() / "serial" / "run.h5");
    Index rows = 0, cols = 0;
    double mass = 0;
    for (double m : reader.read(0, "mass", &rows, &cols))
      mass += m;
    const auto& kinetic = series.column("kinetic_energy");
    const double momentum =
        std::sqrt(2.0 * mass * *std::max_element(kinetic.begin(), kinetic.end()));
    Equality eq{relative, {}, true};
    for (const char* axis : {"x", "y", "z"})
      eq.column_scale[std::string("momentum_") + axis] = momentum;
    // A support's reaction along a free direction is zero up to round-off: every reaction
    // column is judged against the largest reaction of the run.
    double reaction = 0;
    for (const std::string& name : series.names)
      if (name.rfind("reaction_", 0) == 0)
        for (const double v : series.column(name))
          reaction = std::max(reaction, std::abs(v));
    for (const std::string& name : series.names)
      if (name.rfind("reaction_", 0) == 0)
        eq.column_scale[name] = reaction;
    // Likewise a probe's velocity or stress component that symmetry keeps at zero: each is
    // judged against the probe's largest component of the same quantity.
    auto quantity = [](const std::string& name) {
      const auto dot = name.find('.');
      if (dot == std::string::npos || dot + 1 >= name.size())
        return std::string();
      const char q = name[dot + 1];
      return name.substr(0, dot + 1) + (q == 'v' || q == 's' ? q : 'x');
    };
    std::map<std::string, double> largest;
    for (const std::string& name : series.names)
      if (const std::string q = quantity(name); !q.empty())
        for (const double v : series.column(name))
          largest[q] = std::max(largest[q], std::abs(v));
    for (const std::string& name : series.names)
      if (const std::string q = quantity(name); !q.empty())
        eq.column_scale[name] = largest[q];
    expect_same_series(work() / "serial", work() / other, eq);
    expect_same_frames(work() / "serial", work() / other, eq);
  }
};

} // namespace talus::test_support
