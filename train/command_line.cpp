#include "train/command_line.h"

#include <unistd.h>

#include <iostream>

#include "common/command_line.h"
#include "common/config_error.h"
#include "common/exit_codes.h"
#include "common/output_folder.h"
#include "gnn/runtime/runtime.h"

namespace train {

namespace {

// The options of `spill-sim generate`, with the same names and meanings; each needs --scene.
void add_generation_options(CLI::App& app, TrainCommandLine& c) {
  SceneDataOptions& scene = c.scene;
  CLI::Option* scene_option = c.scene_option;
  auto* generate = app.add_option_group(
      "with --scene", "spill-sim generate's options, with the same names and meanings");
  const sph::GenerationOptionHandles added =
      sph::add_generation_options(*generate, scene.generate, c.generation);
  scene_option->needs(added.trajectories);
  added.seed->description(
      "Seed of the --vary draws (the training seed is the training config's /seed)");
  std::vector<CLI::Option*> scene_only = added.all();
  scene_only.push_back(generate->add_option(
      "--set-scene", scene.generate.overrides,
      "override a scene value: /json/pointer=value (spill-sim generate's --set)"));
  scene_only.push_back(generate->add_option(
      "--save-data", scene.save_dir,
      "also write the simulated trajectories to this new folder as a dataset (metadata.json, "
      "train.h5, valid.h5, test.h5), the files spill-sim generate writes"));
  for (CLI::Option* option : scene_only) option->needs(scene_option);
}

}  // namespace

void add_training_options(CLI::App& app, TrainCommandLine& c) {
  TrainerOptions& options = c.options;
  SceneDataOptions& scene = c.scene;
  int& threads = c.threads;
  int& blas_threads = c.blas_threads;
  std::string& device = c.device;
  app.add_option("--config", options.config_file, "training config (configs/training/*.json)")
      ->required()
      ->check(CLI::ExistingFile);
  auto* source = app.add_option_group("data", "Where the trajectories come from");
  auto* data_option =
      source
          ->add_option("--data", options.data_dir,
                       "dataset folder (metadata.json, train.h5, valid.h5) from spill-sim generate")
          ->check(CLI::ExistingDirectory);
  CLI::Option*& scene_option = c.scene_option;
  scene_option = source->add_option(
      "--scene", scene.generate.scene_file,
      "scene JSON file: simulate the training, validation and test trajectories in this process, "
      "as `spill-sim generate` would with the options below, and train on them without a file");
  source->require_option(1);
  data_option->excludes(scene_option);
  scene_option->excludes(data_option);
  add_generation_options(app, c);
  app.add_option("--out", options.out_dir, "run folder: log.csv, loss.svg, last.pt")->required();
  app.add_option("--teacher", options.teacher,
                 "distil a PAGATNet student from this frozen PAGATNet checkpoint (RUN/last.pt "
                 "of the teacher's run, trained on the same data)");
  app.add_flag("--resume", options.resume,
               "continue from RUN/last.pt (with --scene the data are simulated again from the "
               "same seed and must come out bit-identical: on --threads 1)");
  app.add_option("--threads", threads,
                 "cores to use (also by the --scene simulation; 1 makes its data "
                 "bit-reproducible); the LibTorch/BLAS split is chosen for the model (see "
                 "training_runtime in gnn/runtime/runtime.h) unless --blas-threads is given")
      ->check(common::positive());
  app.add_option("--blas-threads", blas_threads,
                 "OpenBLAS threads, with --threads LibTorch threads (default: the measured best "
                 "split for the model)")
      ->check(common::positive());
  app.add_option("--set", options.overrides,
                 "override a training config value: /pointer=value (e.g. /steps=200, "
                 "/model/latent=64)");
  app.add_option("--device", device, "where the model trains: cpu (default) or cuda[:N]");
  app.add_option("--collective-timeout", c.collective_timeout_s,
                 "under torchrun or srun (data-parallel): seconds a rank waits for the others "
                 "in a collective before it stops with an error")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 86400.0));
  app.footer(
      "With --scene the trajectories are simulated in this process, as `spill-sim generate` "
      "simulates them for the same options (the same draws from --seed, splits, warm-up and "
      "normalisation statistics), and trained on as on that dataset with --data, without a file "
      "(unless --save-data). Progress is shown per trajectory; a bad scene, --vary pointer or "
      "--save-data folder exits 2 before anything is simulated or written. --resume simulates "
      "them again and goes on only when they come out bit-identical (on --threads 1 they do).");
}

void run_training(TrainCommandLine& c) {
  TrainerOptions& options = c.options;
  SceneDataOptions& scene = c.scene;
  int& threads = c.threads;
  int& blas_threads = c.blas_threads;
  std::string& device = c.device;
  gnn::configure_runtime({threads, blas_threads});
  // Under torchrun or srun: join the other ranks (train/data_parallel.h); rank 0 alone prints.
  const LaunchEnvironment launch = read_launch_environment();
  std::unique_ptr<DataParallel> parallel;
  if (launch.world > 1) {
    parallel = DataParallel::connect(
        launch, std::chrono::milliseconds(std::int64_t(c.collective_timeout_s * 1000)));
    options.parallel = parallel.get();
    if (launch.rank == 0)
      std::cerr << "data-parallel: " << launch.world << " ranks (" << launch.launcher
                << "), rank 0 writes " << options.out_dir << "\n";
  }
  options.log = launch.rank == 0 ? &std::cerr : nullptr;
  options.terminal = isatty(2);
  options.out_dir = common::normalise_output_path(options.out_dir).string();
  options.device = gnn::parse_device(device);
  std::unique_ptr<Trainer> trainer;
  if (*c.scene_option) {
    for (const auto& v : c.generation.vary)
      scene.generate.vary.push_back(sph::parse_parameter_range(v));
    scene.generate.split = sph::parse_split(c.generation.split);
    scene.generate.threads = threads;
    scene.generate.log = options.log;
    scene.generate.stop = options.stop;  // an interrupted simulation writes no --save-data
    if (!scene.save_dir.empty() &&
        common::normalise_output_path(scene.save_dir).string() == options.out_dir)
      throw common::InputError("--save-data " + scene.save_dir + ": is the run folder (--out)");
    // The simulation runs on all --threads (configure_runtime set OpenMP's count; the recorder
    // keeps it through LibTorch's first operation); the training's own split comes after.
    trainer =
        std::make_unique<Trainer>(options, [&] { return simulate_training_data(scene, options); });
  } else {
    trainer = std::make_unique<Trainer>(options);
  }
  if (blas_threads == 0) {
    const gnn::GraphModel& model = trainer->simulator().model();
    const gnn::RuntimeSettings mix = gnn::training_runtime(threads, model.trains_in_chunks());
    gnn::configure_runtime(mix);
    if (launch.rank == 0)
      std::cerr << "threads: " << mix.threads << " LibTorch, " << mix.blas_threads
                << " BLAS (the measured best split for " << model.name() << " on " << threads
                << "), " << gnn::blas_kernels() << " BLAS kernels\n";
  }
  const double loss = trainer->run();
  if (launch.rank != 0) return;
  std::cout << "trained to step " << trainer->step() << ", loss " << loss << "; run in "
            << options.out_dir << "\n";
}

}  // namespace train
