// spill-sim generate --scene FILE --trajectories N --out DIR [--vary /pointer=LO:HI ...]
//                    [--seed S] [--split 0.8/0.1/0.1] [--frames F] [--warm-up S] [--threads N]

#include <iostream>
#include <memory>

#include "common/command_line.h"
#include "common/output_folder.h"
#include "sph/app/commands/command.h"
#include "sph/generation/dataset_folder.h"

namespace sph {

namespace {
struct GenerateCommandOptions {
  GenerateOptions generate;
  std::string out_dir, split = "0.8/0.1/0.1";
  std::vector<std::string> vary;
  int threads = 1;
};
}  // namespace

Command add_generate_command(CLI::App& app, const CommandContext& context) {
  auto o = std::make_shared<GenerateCommandOptions>();
  GenerateOptions& g = o->generate;
  auto* c = app.add_subcommand(
      "generate", "Simulate N trajectories with drawn parameters into train/valid/test.h5");
  c->add_option("--scene", g.scene_file, "Scene JSON file")->required();
  c->add_option("--trajectories", g.trajectories, "Number of trajectories")
      ->required()
      ->check(common::positive());
  c->add_option("--out", o->out_dir, "Dataset folder (resumed if it holds a partial run)")
      ->required();
  c->add_option("--vary", o->vary, "Draw a scene value per trajectory: /pointer=LO:HI");
  c->add_option("--seed", g.seed, "Seed of the draws")->capture_default_str();
  c->add_option("--split", o->split, "Train/valid/test fractions")->capture_default_str();
  c->add_option("--frames", g.frames,
                "Recorded frames per trajectory after the warm-up (default: to the end)")
      ->check(common::positive());
  c->add_option("--warm-up", g.warm_up,
                "Seconds simulated before recording (default: the first leak's start)")
      ->check(common::non_negative());
  c->add_option("--set", g.overrides, "Override a scene value: /json/pointer=value");
  c->add_option("--threads", o->threads,
                "OpenMP threads (1, the default, makes datasets bit-reproducible)")
      ->capture_default_str()
      ->check(common::positive());
  return {c, [o, context] {
            context.catch_stop_signals();
            GenerateOptions options = o->generate;
            options.out_dir = common::normalise_output_path(o->out_dir);
            for (const auto& v : o->vary) options.vary.push_back(parse_parameter_range(v));
            options.split = parse_split(o->split);
            options.threads = use_threads(o->threads);
            options.stop = context.stop;
            options.log = &std::cerr;
            const nlohmann::json meta = generate_dataset(options);
            std::cout << "wrote " << o->out_dir << ": " << meta["counts"].dump()
                      << " trajectories\n";
            return 0;
          }};
}

}  // namespace sph
