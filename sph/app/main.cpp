// spill-sim: runs SPH scenes. A thin front over the sph library (see scene_runner.h).
//   spill-sim run --scene FILE --out DIR [--set /pointer=value ...] [--threads N] [--ply] [--png]
//                 [--force] [--save-state-at T] [--initial-state FILE]
//   spill-sim bench [--scene FILE] [--radius R ...] [--threads N] [--set ...]
//   spill-sim bench --scene FILE --compare mtdf,dfsph [--repeat N] [--threads N] [--set ...]
//   spill-sim generate --scene FILE --trajectories N --out DIR [--vary /pointer=LO:HI ...]
//                      [--seed S] [--split 0.8/0.1/0.1] [--frames F] [--warm-up S] [--threads N]
//   spill-sim compare --scene FILE --solvers wcsph,dfsph,... --frames T1,T2,... --out DIR
//                     [--set /pointer=value ...] [--threads N] [--force]
//       runs the scene with each solver to the last of the frame counts and writes table.json,
//       table.md (wall time to each moment, throughput, iterations, density error, spill
//       metrics) and views.png (a column per solver, a row per moment); exits 1 only when every
//       solver failed (see solver_table.h)
//   spill-sim scene-doc

#include <omp.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <iostream>
#include <stdexcept>

#include "common/command_line.h"
#include "common/exit_codes.h"
#include "common/hdf5_handles.h"
#include "common/output_folder.h"
#include "sph/app/dataset_generator.h"
#include "sph/app/scene_runner.h"
#include "sph/app/solver_comparison.h"
#include "sph/app/solver_table.h"
#include "sph/core/config.h"
#include "sph/core/floating_point.h"
#include "sph/scene/scene_loader.h"

namespace {

// Signal handlers can only reach static storage; this flag is read by the run loop, which then
// removes its staging folder and exits.
std::atomic<bool> g_stop_requested{false};
void request_stop(int) {
  g_stop_requested.store(true);
}

int thread_count(int requested) {
  const int n = requested > 0 ? requested : omp_get_num_procs();
  omp_set_num_threads(n);
  sph::flush_subnormals_to_zero();
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  common::skip_hdf5_exit_handler();
  CLI::App app{"spill-sim: two-phase SPH simulation of oil spills in rivers"};
  app.require_subcommand(1);

  std::string scene_file, out_dir;
  std::vector<std::string> overrides;
  int threads = 0;
  bool ply = false, png = false, force = false;
  auto* run = app.add_subcommand("run", "Simulate a scene and write its run folder");
  run->add_option("--scene", scene_file, "Scene JSON file")->required();
  run->add_option("--out", out_dir, "Output folder (not replaced unless --force)")->required();
  run->add_option("--set", overrides, "Override a scene value: /json/pointer=value");
  run->add_option("--threads", threads, "OpenMP threads (default: all cores)")
      ->check(CLI::PositiveNumber);
  run->add_flag("--ply", ply, "Write a PLY file per frame");
  run->add_flag("--png", png, "Write side- and top-view PNG pictures per frame");
  run->add_flag(
      "--force", force,
      "Replace an earlier run folder (only one of ours; it is removed after the new run succeeds)");
  std::string initial_state;
  double save_state_at = -1;
  run->add_option("--initial-state", initial_state,
                  "Continue from a state saved by --save-state-at (e.g. after a river's warm-up)");
  run->add_option("--save-state-at", save_state_at,
                  "Save the state at this frame time to DIR/state.h5")
      ->check(CLI::NonNegativeNumber);

  std::string bench_scene = "configs/scenes/dam_break.json";
  std::vector<double> radii;
  int bench_threads = 2;
  std::vector<std::string> bench_overrides;
  auto* bench = app.add_subcommand("bench", "Measure solver throughput; prints JSON");
  bench->add_option("--scene", bench_scene, "Scene JSON file")->capture_default_str();
  bench->add_option("--radius", radii, "Particle radii to run (default: the scene's)");
  bench->add_option("--threads", bench_threads, "OpenMP threads")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  bench->add_option("--set", bench_overrides, "Override a scene value: /json/pointer=value");
  std::vector<std::string> compare_solvers;
  int repeat = 3;
  bench
      ->add_option("--compare", compare_solvers,
                   "Compare solvers on the scene, runs alternating (e.g. mtdf,dfsph); the "
                   "ratio is the first's median wall time over the second's")
      ->delimiter(',');
  bench->add_option("--repeat", repeat, "Runs of each solver with --compare")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);

  sph::GenerateOptions gen;
  std::string gen_scene, gen_out, gen_split = "0.8/0.1/0.1";
  std::vector<std::string> gen_vary, gen_overrides;
  int gen_threads = 1;
  auto* generate = app.add_subcommand(
      "generate", "Simulate N trajectories with drawn parameters into train/valid/test.h5");
  generate->add_option("--scene", gen_scene, "Scene JSON file")->required();
  generate->add_option("--trajectories", gen.trajectories, "Number of trajectories")
      ->required()
      ->check(CLI::PositiveNumber);
  generate->add_option("--out", gen_out, "Dataset folder (resumed if it holds a partial run)")
      ->required();
  generate->add_option("--vary", gen_vary, "Draw a scene value per trajectory: /pointer=LO:HI");
  generate->add_option("--seed", gen.seed, "Seed of the draws")->capture_default_str();
  generate->add_option("--split", gen_split, "Train/valid/test fractions")->capture_default_str();
  generate
      ->add_option("--frames", gen.frames,
                   "Recorded frames per trajectory after the warm-up (default: to the end)")
      ->check(CLI::PositiveNumber);
  generate
      ->add_option("--warm-up", gen.warm_up,
                   "Seconds simulated before recording (default: the first leak's start)")
      ->check(CLI::NonNegativeNumber);
  generate->add_option("--set", gen_overrides, "Override a scene value: /json/pointer=value");
  generate
      ->add_option("--threads", gen_threads,
                   "OpenMP threads (1, the default, makes datasets bit-reproducible)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);

  sph::SolverTableRequest table;
  int table_threads = 0;
  auto* compare = app.add_subcommand(
      "compare",
      "Run a scene with each solver; write a table (table.md, table.json) and a picture grid "
      "(views.png)");
  compare->add_option("--scene", table.scene_file, "Scene JSON file")->required();
  compare
      ->add_option("--solvers", table.solvers,
                   "Registered solvers, comma-separated, in column order (e.g. wcsph,dfsph,mtdf)")
      ->required()
      ->delimiter(',');
  compare
      ->add_option("--frames", table.frames,
                   "Moments, increasing, in frames of the scene's output/frame_dt, "
                   "comma-separated (e.g. 40,80,120); every solver runs to the last")
      ->required()
      ->delimiter(',');
  compare->add_option("--out", out_dir, "Output folder (not replaced unless --force)")->required();
  compare->add_option("--set", table.overrides, "Override a scene value: /json/pointer=value");
  compare->add_option("--threads", table_threads, "OpenMP threads (default: all cores)")
      ->check(CLI::PositiveNumber);
  compare->add_flag("--force", table.force,
                    "Replace an earlier compare folder (removed after the new one is written)");
  compare->footer(
      "A solver that fails is marked in the table with its frame and reason, its later pictures "
      "are grey, and the others still run. Exit code: 0 when at least one solver finished; 1 "
      "when every solver failed (nothing is written); 2 for bad input (an unknown solver, a bad "
      "scene or option, a refused --out); 130 when interrupted (nothing is written).");

  auto* doc = app.add_subcommand("scene-doc", "Print the scene parameter reference (Markdown)");

  if (const auto stop = common::parse_command_line(app, argc, argv)) return *stop;

  try {
    if (*doc) {
      std::cout << sph::scene_reference_markdown();
      return 0;
    }
    if (*run) {
      std::signal(SIGINT, request_stop);
      std::signal(SIGTERM, request_stop);
      const sph::LoadedScene scene = sph::load_scene(scene_file, overrides);
      sph::RunOptions options;
      options.out_dir = out_dir;
      options.force = force;
      options.ply = ply;
      options.png = png;
      options.threads = thread_count(threads);
      options.stop = &g_stop_requested;
      options.log = &std::cerr;
      options.terminal = isatty(STDERR_FILENO) != 0;
      options.initial_state = initial_state;
      options.save_state_at = save_state_at;
      const nlohmann::json summary = sph::run_scene(scene, options);
      std::cout << "wrote " << out_dir << ": " << summary["steps"] << " steps, "
                << summary["fluid_particles"] << " fluid particles, "
                << summary["particle_steps_per_s"].get<double>() << " particle-steps/s\n";
      return 0;
    }
    if (*compare) {
      std::signal(SIGINT, request_stop);
      std::signal(SIGTERM, request_stop);
      table.out_dir = out_dir;
      table.threads = thread_count(table_threads);
      table.stop = &g_stop_requested;
      table.log = &std::cerr;
      table.terminal = isatty(STDERR_FILENO) != 0;
      const nlohmann::json written = sph::write_solver_table(table);
      int failed = 0;
      for (const auto& row : written["rows"]) failed += row["status"] != "ok";
      std::cout << "wrote " << out_dir << ": " << written["rows"].size() << " solvers"
                << (failed ? " (" + std::to_string(failed) + " failed, see table.md)" : "")
                << ", views.png " << written["views"]["width"] << " x "
                << written["views"]["height"] << "\n";
      return 0;
    }
    if (*generate) {
      std::signal(SIGINT, request_stop);
      std::signal(SIGTERM, request_stop);
      gen.scene_file = gen_scene;
      gen.out_dir = common::normalise_output_path(gen_out);
      gen.overrides = gen_overrides;
      for (const auto& v : gen_vary) gen.vary.push_back(sph::parse_parameter_range(v));
      gen.split = sph::parse_split(gen_split);
      gen.threads = thread_count(gen_threads);
      gen.stop = &g_stop_requested;
      gen.log = &std::cerr;
      const nlohmann::json meta = sph::generate_dataset(gen);
      std::cout << "wrote " << gen_out << ": " << meta["counts"].dump() << " trajectories\n";
      return 0;
    }
    if (*bench) {
      const int n = thread_count(bench_threads);
      if (!compare_solvers.empty()) {
        if (!radii.empty())
          throw common::InputError(
              "--compare takes the scene's radius; change it with --set /particle_radius=R");
        sph::SolverComparison comparison;
        comparison.scene_file = bench_scene;
        comparison.overrides = bench_overrides;
        comparison.solvers = compare_solvers;
        comparison.repeat = repeat;
        comparison.threads = n;
        nlohmann::json out = {{"benchmark", "spill-sim bench --compare"},
                              {"scene_file", bench_scene},
                              {"machine", sph::machine_description(n)}};
        out.update(sph::compare_solvers(comparison, &std::cerr));
        std::cout << out.dump(2) << "\n";
        return 0;
      }
      nlohmann::json results = nlohmann::json::array();
      if (radii.empty()) radii.push_back(-1);
      for (double r : radii) {
        std::vector<std::string> o = bench_overrides;
        if (r > 0) o.push_back("/particle_radius=" + std::to_string(r));
        const sph::LoadedScene scene = sph::load_scene(bench_scene, o);
        results.push_back(sph::benchmark_scene(scene, n, &std::cerr));
      }
      std::cout << nlohmann::json{{"benchmark", "spill-sim bench"},
                                  {"scene_file", bench_scene},
                                  {"machine", sph::machine_description(n)},
                                  {"results", results}}
                       .dump(2)
                << "\n";
      return 0;
    }
  } catch (const std::exception& e) {
    return common::report_error(std::cerr, "spill-sim", e);
  }
  return 0;
}
