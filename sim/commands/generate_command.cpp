// spill-sim generate --scene FILE --trajectories N --out DIR [--vary /pointer=LO:HI ...]
//                    [--seed S] [--split 0.8/0.1/0.1] [--frames F] [--warm-up S] [--threads N]
//                    [--shard I/N]
// spill-sim generate --assemble --out DIR
// A shard defaults to a Slurm job array's task (SLURM_ARRAY_TASK_ID less SLURM_ARRAY_TASK_MIN,
// of SLURM_ARRAY_TASK_COUNT), so an array job needs no --shard.

#include <iostream>
#include <memory>
#include <optional>

#include "common/array_task.h"
#include "common/command_line.h"
#include "common/output_folder.h"
#include "sim/commands/command.h"
#include "sph/generation/dataset_folder.h"
#include "sph/generation/generation_command_line.h"

namespace sim {

namespace {
struct GenerateCommandOptions {
  sph::GenerateOptions generate;
  std::string out_dir, shard;
  sph::GenerationOptionText text;  // --vary, --split
  int threads = 1;
  bool assemble = false;
};

// --shard, else the Slurm array task this process is, else the whole request.
sph::GenerationShard shard_of(const std::string& option) {
  if (!option.empty()) return sph::parse_shard(option);
  const std::optional<common::ArrayTask> task = common::slurm_array_task();
  if (!task) return {};
  return {task->index, task->count, false};
}
}  // namespace

Command add_generate_command(CLI::App& app, const CommandContext& context) {
  auto o = std::make_shared<GenerateCommandOptions>();
  sph::GenerateOptions& g = o->generate;
  auto* c = app.add_subcommand(
      "generate", "Simulate N trajectories with drawn parameters into train/valid/test.h5");
  auto* scene = c->add_option("--scene", g.scene_file, "Scene JSON file");
  c->add_option("--out", o->out_dir, "Dataset folder (resumed if it holds a partial run)")
      ->required();
  CLI::Option* trajectories = sph::add_generation_options(*c, g, o->text).trajectories;
  c->add_option("--set", g.overrides, "Override a scene value: /json/pointer=value");
  c->add_option("--threads", o->threads,
                "OpenMP threads (1, the default, makes datasets bit-reproducible)")
      ->capture_default_str()
      ->check(common::positive());
  c->add_option("--shard", o->shard,
                "Simulate only shard I of N (trajectories i with i mod N = I) into the folder's "
                "parts/; default: the Slurm array task, if any");
  c->add_flag("--assemble", o->assemble,
              "Only assemble the splits and metadata.json of a sharded generation in --out")
      ->excludes(scene)
      ->excludes(trajectories);
  return {c, [o, context] {
            context.catch_stop_signals();
            const std::filesystem::path out_dir = common::normalise_output_path(o->out_dir);
            sph::GenerateOptions options;
            if (o->assemble) {
              options = sph::stored_generation(out_dir);
            } else {
              if (o->generate.scene_file.empty() || o->generate.trajectories < 1)
                throw common::InputError(
                    "generate: --scene and --trajectories are required (or --assemble)");
              options = o->generate;
              options.out_dir = out_dir;
              for (const auto& v : o->text.vary)
                options.vary.push_back(sph::parse_parameter_range(v));
              options.split = sph::parse_split(o->text.split);
              options.shard = shard_of(o->shard);
            }
            if (o->assemble)
              use_threads(1);  // the stored invocation's count stays in the metadata
            else
              options.threads = use_threads(o->threads);
            options.stop = context.stop;
            options.log = &std::cerr;
            const sph::GenerationResult result = sph::generate_dataset(options);
            if (result.metadata.is_null()) {
              std::cout << "shard " << options.shard.index << "/" << options.shard.count
                        << ": simulated " << result.simulated << " trajectories into " << o->out_dir
                        << "/parts; " << result.missing.size()
                        << " of other shards are not finished yet (the last shard to finish "
                           "assembles the dataset, or: spill-sim generate --assemble --out "
                        << o->out_dir << ")\n";
              return 0;
            }
            std::cout << "wrote " << o->out_dir << ": " << result.metadata["counts"].dump()
                      << " trajectories\n";
            return 0;
          }};
}

}  // namespace sim
