#include "sph/app/solver_comparison.h"

#include <algorithm>
#include <stdexcept>

#include "sph/app/scene_runner.h"
#include "sph/core/config.h"
#include "sph/scene/scene_loader.h"

namespace sph {

namespace {

double forces_entry(const nlohmann::json& run, const char* force) {
  const auto& forces = run.at("time_split").at("forces");
  return forces.contains(force) ? forces.at(force).get<double>() : 0.0;
}

}  // namespace

std::vector<LoadedScene> load_scene_per_solver(const std::string& scene_file,
                                               const std::vector<std::string>& overrides,
                                               const std::vector<std::string>& solvers,
                                               const std::string& option) {
  const std::vector<std::string> known = pressure_solver_names();
  for (const std::string& solver : solvers)
    if (std::find(known.begin(), known.end(), solver) == known.end()) {
      std::string list;
      for (const auto& name : known) list += (list.empty() ? "" : ", ") + name;
      throw common::InputError(option + ": unknown solver \"" + solver + "\" (registered: " + list +
                               ")");
    }
  std::vector<LoadedScene> scenes;
  for (const std::string& solver : solvers) {
    std::vector<std::string> with_solver = overrides;
    with_solver.push_back("/solver=\"" + solver + "\"");
    scenes.push_back(load_scene(scene_file, with_solver));
  }
  return scenes;
}

nlohmann::json compare_solvers(const SolverComparison& comparison, std::ostream* log) {
  if (comparison.solvers.size() < 2)
    throw common::InputError(
        "--compare needs at least two solvers, comma-separated (e.g. mtdf,dfsph)");
  if (comparison.repeat < 1) throw common::InputError("--repeat must be at least 1");
  // Load every variant before running any, so that a bad solver name fails at once.
  const std::vector<LoadedScene> scenes = load_scene_per_solver(
      comparison.scene_file, comparison.overrides, comparison.solvers, "--compare");
  std::vector<std::vector<nlohmann::json>> runs(scenes.size());
  for (int r = 0; r < comparison.repeat; ++r)
    for (size_t s = 0; s < scenes.size(); ++s) {
      if (log)
        *log << "run " << r + 1 << "/" << comparison.repeat << " of " << comparison.solvers[s]
             << "\n";
      runs[s].push_back(benchmark_scene(scenes[s], comparison.threads, log));
    }

  nlohmann::json walls = nlohmann::json::object(), medians = nlohmann::json::object(),
                 mixture = nlohmann::json::object(), tension = nlohmann::json::object(),
                 results = nlohmann::json::array();
  std::vector<double> median_wall;
  for (size_t s = 0; s < scenes.size(); ++s) {
    std::vector<nlohmann::json> sorted = runs[s];
    std::sort(sorted.begin(), sorted.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
      return a.at("wall_s").get<double>() < b.at("wall_s").get<double>();
    });
    // The lower median for an even count: a real run, not an average of two.
    const nlohmann::json& median = sorted[(sorted.size() - 1) / 2];
    const std::string& name = comparison.solvers[s];
    walls[name] = nlohmann::json::array();
    for (const auto& run : runs[s]) walls[name].push_back(run.at("wall_s"));
    medians[name] = median.at("wall_s");
    mixture[name] = median.at("time_split").value("mixture_model", 0.0);
    tension[name] = forces_entry(median, "surface_tension");
    results.push_back(median);
    median_wall.push_back(median.at("wall_s").get<double>());
  }
  return {{"scene", scenes[0].config.name},
          {"solvers", comparison.solvers},
          {"repeat", comparison.repeat},
          {"wall_s", walls},
          {"median_wall_s", medians},
          {"ratio", median_wall[0] / median_wall[1]},
          {"ratio_of", comparison.solvers[0] + " / " + comparison.solvers[1] + " median wall time"},
          {"mixture_model_s", mixture},
          {"surface_tension_s", tension},
          {"results", results}};
}

}  // namespace sph
