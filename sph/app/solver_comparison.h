#pragma once
// Compares pressure solvers on one scene in one process (`spill-sim bench --compare`): the runs
// alternate between the solvers, so a slow spell of a shared machine falls on all of them, and
// each solver's median run is reported with the ratio of the first solver's median wall time to
// the second's.

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "sph/scene/scene_loader.h"

namespace sph {

// The scene loaded once per solver, each with "/solver=NAME" after `overrides`, in the order of
// `solvers`. Every name is checked against the registry before any scene is loaded: an unknown
// one is a common::InputError naming `option`, the name and the registered solvers. Throws
// ConfigError for a bad scene or override.
std::vector<LoadedScene> load_scene_per_solver(const std::string& scene_file,
                                               const std::vector<std::string>& overrides,
                                               const std::vector<std::string>& solvers,
                                               const std::string& option);

struct SolverComparison {
  std::string scene_file;
  std::vector<std::string> overrides;  // applied to every run, before the solver is set
  std::vector<std::string> solvers;    // at least two; the ratio is solvers[0] / solvers[1]
  int repeat = 3;                      // runs of each solver
  int threads = 1;                     // recorded (the caller sets OpenMP's thread count)
};

// Returns {"scene", "solvers", "repeat", "wall_s": {solver: [runs]}, "median_wall_s",
// "ratio", "mixture_model_s", "surface_tension_s", "results": [median run of each solver]}.
// Throws common::InputError for an unknown solver, fewer than two solvers or no repeat,
// ConfigError for a bad scene.
nlohmann::json compare_solvers(const SolverComparison& comparison, std::ostream* log);

}  // namespace sph
