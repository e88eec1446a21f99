// spill-sim run --scene FILE --out DIR [--set /pointer=value ...] [--threads N] [--ply] [--png]
//               [--vtk] [--force] [--save-state-at T] [--initial-state FILE]

#include <unistd.h>

#include <iostream>
#include <memory>

#include "common/command_line.h"
#include "sim/commands/command.h"
#include "sph/app/scene_runner.h"
#include "sph/scene/scene_loader.h"

namespace sim {

namespace {
struct RunCommandOptions {
  std::string scene_file, out_dir;
  std::vector<std::string> overrides;
  int threads = 0;
  sph::RunOptions run;
};
}  // namespace

Command add_run_command(CLI::App& app, const CommandContext& context) {
  auto o = std::make_shared<RunCommandOptions>();
  auto* c = app.add_subcommand("run", "Simulate a scene and write its run folder");
  c->add_option("--scene", o->scene_file, "Scene JSON file")->required();
  c->add_option("--out", o->out_dir, "Output folder (not replaced unless --force)")->required();
  c->add_option("--set", o->overrides, "Override a scene value: /json/pointer=value");
  c->add_option("--threads", o->threads, "OpenMP threads (default: all cores)")
      ->check(common::positive());
  c->add_flag("--ply", o->run.ply, "Write a PLY file per frame");
  c->add_flag("--png", o->run.png, "Write side- and top-view PNG pictures per frame");
  c->add_flag("--vtk", o->run.vtk,
              "Write VTK (ParaView) point files per frame in vtk/ with a fluid.pvd collection");
  c->add_flag(
      "--force", o->run.force,
      "Replace an earlier run folder (only one of ours; it is removed after the new run succeeds)");
  c->add_option("--initial-state", o->run.initial_state,
                "Continue from a state saved by --save-state-at (e.g. after a river's warm-up)");
  c->add_option("--save-state-at", o->run.save_state_at,
                "Save the state at this frame time to DIR/state.h5")
      ->check(common::non_negative());
  return {c, [o, context] {
            context.catch_stop_signals();
            const sph::LoadedScene scene = sph::load_scene(o->scene_file, o->overrides);
            sph::RunOptions options = o->run;
            options.out_dir = o->out_dir;
            options.threads = use_threads(o->threads);
            options.stop = context.stop;
            options.log = &std::cerr;
            options.terminal = isatty(STDERR_FILENO) != 0;
            const nlohmann::json summary = sph::run_scene(scene, options);
            std::cout << "wrote " << o->out_dir << ": " << summary["steps"] << " steps, "
                      << summary["fluid_particles"] << " fluid particles, "
                      << summary["particle_steps_per_s"].get<double>() << " particle-steps/s\n";
            return 0;
          }};
}

}  // namespace sim
