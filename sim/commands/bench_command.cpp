// spill-sim bench [--scene FILE] [--radius R ...] [--threads N] [--set ...]        prints JSON
// spill-sim bench --scene FILE --compare mtdf,dfsph [--repeat N] [--threads N] [--set ...]

#include <iostream>
#include <memory>

#include "common/command_line.h"
#include "common/exit_codes.h"
#include "sim/commands/command.h"
#include "sph/app/scene_runner.h"
#include "sph/app/solver_comparison.h"
#include "sph/scene/scene_loader.h"

namespace sim {

namespace {

struct BenchCommandOptions {
  std::string scene_file = "configs/scenes/dam_break.json";
  std::vector<double> radii;
  int threads = 2;
  std::vector<std::string> overrides;
  std::vector<std::string> compare_solvers;
  int repeat = 3;
};

// Solver against solver on one scene, runs alternating.
nlohmann::json bench_compare(const BenchCommandOptions& o, int threads) {
  if (!o.radii.empty())
    throw common::InputError(
        "--compare takes the scene's radius; change it with --set /particle_radius=R");
  sph::SolverComparison comparison;
  comparison.scene_file = o.scene_file;
  comparison.overrides = o.overrides;
  comparison.solvers = o.compare_solvers;
  comparison.repeat = o.repeat;
  comparison.threads = threads;
  nlohmann::json out = {{"benchmark", "spill-sim bench --compare"},
                        {"scene_file", o.scene_file},
                        {"machine", sph::machine_description(threads)}};
  out.update(sph::compare_solvers(comparison, &std::cerr));
  return out;
}

// The scene's throughput at each particle radius (the scene's own without --radius).
nlohmann::json bench_radii(const BenchCommandOptions& o, int threads) {
  nlohmann::json results = nlohmann::json::array();
  std::vector<double> radii = o.radii;
  if (radii.empty()) radii.push_back(-1);
  for (double r : radii) {
    std::vector<std::string> overrides = o.overrides;
    if (r > 0) overrides.push_back("/particle_radius=" + std::to_string(r));
    const sph::LoadedScene scene = sph::load_scene(o.scene_file, overrides);
    results.push_back(sph::benchmark_scene(scene, threads, &std::cerr));
  }
  return {{"benchmark", "spill-sim bench"},
          {"scene_file", o.scene_file},
          {"machine", sph::machine_description(threads)},
          {"results", results}};
}

}  // namespace

Command add_bench_command(CLI::App& app, const CommandContext&) {
  auto o = std::make_shared<BenchCommandOptions>();
  auto* c = app.add_subcommand("bench", "Measure solver throughput; prints JSON");
  c->add_option("--scene", o->scene_file, "Scene JSON file")->capture_default_str();
  c->add_option("--radius", o->radii, "Particle radii to run (default: the scene's)");
  c->add_option("--threads", o->threads, "OpenMP threads")
      ->capture_default_str()
      ->check(common::positive());
  c->add_option("--set", o->overrides, "Override a scene value: /json/pointer=value");
  c->add_option("--compare", o->compare_solvers,
                "Compare solvers on the scene, runs alternating (e.g. mtdf,dfsph); the "
                "ratio is the first's median wall time over the second's")
      ->delimiter(',');
  c->add_option("--repeat", o->repeat, "Runs of each solver with --compare")
      ->capture_default_str()
      ->check(common::positive());
  return {c, [o] {
            const int threads = use_threads(o->threads);
            const nlohmann::json out =
                o->compare_solvers.empty() ? bench_radii(*o, threads) : bench_compare(*o, threads);
            std::cout << out.dump(2) << "\n";
            return 0;
          }};
}

}  // namespace sim
