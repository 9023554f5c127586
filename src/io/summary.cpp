// summary.json: the outcome of a run in one JSON object, written atomically (file.tmp, then
// rename) so a reader sees either the previous summary or the complete new one.
#include "talus/io/results.hpp"

#include <nlohmann/json.hpp>

#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace talus {

void write_summary_json(const std::filesystem::path& file, const RunSummary& s) {
  nlohmann::ordered_json j;
  j["case"] = s.case_name;
  j["status"] = s.status;
  j["message"] = s.message;
  j["steps"] = s.steps;
  j["final_time"] = s.final_time;
  j["particles"] = s.particles;
  j["frames"] = s.frames;
  j["wall_seconds"] = s.wall_seconds;
  if (!s.linear_solver.empty())
    j["linear_solver"] = s.linear_solver;
  for (const auto& [key, value] : s.extra) {
    if (j.contains(key))
      throw std::invalid_argument("write_summary_json: extra entry '" + key +
                                  "' would replace a standard field");
    j[key] = value;
  }
  for (const StageSummary& stage : s.stages)
    j["stages"].push_back({{"name", stage.name},
                           {"analysis", stage.analysis},
                           {"strength_factor", stage.strength_factor},
                           {"start_time", stage.start_time},
                           {"end_time", stage.end_time},
                           {"steps", stage.steps},
                           {"wall_seconds", stage.wall_seconds},
                           {"end", stage.end}});
  // Non-finite numbers have no JSON spelling; nlohmann writes them as null.
  const std::string text = j.dump(2) + "\n";

  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out)
      throw std::runtime_error("cannot create '" + tmp.string() + "'");
    out << text;
    out.flush();
    if (!out)
      throw std::runtime_error("cannot write '" + tmp.string() + "'");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec)
    throw std::runtime_error("cannot rename '" + tmp.string() + "' to '" + file.string() +
                             "': " + ec.message());
}

} // namespace talus
