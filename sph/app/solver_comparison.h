#pragma once
// Compares pressure solvers on one scene in one process (`spill-sim bench --compare`): the runs
// alternate between the solvers, so a slow spell of a shared machine falls on all of them, and
// each solver's median run is reported with the ratio of the first solver's median wall time to
// the second's.

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace sph {

struct SolverComparison {
  std::string scene_file;
  std::vector<std::string> overrides;  // applied to every run, before the solver is set
  std::vector<std::string> solvers;    // at least two; the ratio is solvers[0] / solvers[1]
  int repeat = 3;                      // runs of each solver
  int threads = 1;                     // recorded (the caller sets OpenMP's thread count)
};

// Returns {"scene", "solvers", "repeat", "wall_s": {solver: [runs]}, "median_wall_s",
// "ratio", "mixture_model_s", "surface_tension_s", "results": [median run of each solver]}.
// Throws ConfigError for an unknown solver or a bad scene, common::InputError for fewer than
// two solvers or no repeat.
nlohmann::json compare_solvers(const SolverComparison& comparison, std::ostream* log);

}  // namespace sph
