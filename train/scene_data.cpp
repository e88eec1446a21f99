#include "train/scene_data.h"

#include <array>
#include <filesystem>
#include <sstream>

#include "common/config_error.h"
#include "common/json_file.h"
#include "gnn/data/frame_window.h"
#include "gnn/data/simulated_dataset.h"
#include "train/pushforward.h"
#include "train/training_config.h"

namespace train {
namespace fs = std::filesystem;

namespace {

// The parts of a description that decide the data: the scene file and the generation settings,
// without the thread count (which decides only whether they are bit-reproducible).
nlohmann::json deciding(nlohmann::json description) {
  description.erase("fingerprint");
  description.erase("saved_to");
  if (description.contains("generation") && description["generation"].is_object())
    description["generation"].erase("threads");
  return description;
}

}  // namespace

TrainingData simulate_training_data(const SceneDataOptions& options, const TrainerOptions& run) {
  const sph::GenerateOptions& g = options.generate;
  // Training samples the training split and validates on the validation split: both must be
  // there (a dataset folder without one is refused by its reader the same way).
  const std::array<int, 3> counts = sph::split_counts(g.trajectories, g.split);
  if (counts[0] < 1 || counts[1] < 1) {
    std::ostringstream split;
    split << g.split[0] << "/" << g.split[1] << "/" << g.split[2];
    throw common::InputError(
        "--split " + split.str() + " of --trajectories " + std::to_string(g.trajectories) +
        " gives " + std::to_string(counts[0]) + " training and " + std::to_string(counts[1]) +
        " validation trajectories; training needs at least one of each");
  }
  // A training window takes kWindow positions, the pushforward frames and a target per loss frame:
  // with fewer recorded frames every trajectory would be simulated only to be refused afterwards.
  const int needed =
      frames_per_window(load_training_config(run.config_file, run.overrides).training);
  if (g.frames > 0 && g.frames < needed)
    throw common::InputError("--frames " + std::to_string(g.frames) + ": a training window needs " +
                             std::to_string(needed) + " frames of each trajectory (" +
                             std::to_string(gnn::kWindow) +
                             " positions, the config's longest pushforward and its loss frames); "
                             "nothing was simulated");
  nlohmann::json description = {{"scene", fs::absolute(g.scene_file).lexically_normal().string()},
                                {"generation", sph::generation_settings(g)}};
  const std::string config = (fs::path(run.out_dir) / "config.json").string();
  nlohmann::json stored;
  if (run.resume) {
    stored = common::load_json_file(config, "training run config").value("data", nlohmann::json());
    if (!stored.is_object() || !stored.contains("fingerprint"))
      throw common::ConfigError(config, "/data",
                                "the run being resumed was trained on the dataset folder " +
                                    stored.dump() +
                                    ", not on a simulated scene: resume it with "
                                    "--data instead of --scene");
    const nlohmann::json patch = nlohmann::json::diff(deciding(stored), deciding(description));
    if (!patch.empty()) {
      std::string keys;
      for (const auto& op : patch)
        keys += (keys.empty() ? "" : ", ") + op.at("path").get<std::string>();
      throw common::ConfigError(config, "/data" + patch[0].at("path").get<std::string>(),
                                "the run being resumed was trained on data simulated with other "
                                "settings (" +
                                    keys +
                                    " differ): resume it with the same --scene, --trajectories, "
                                    "--vary, --seed, --split, --frames, --warm-up and --set-scene");
    }
  }
  gnn::SimulatedDataset simulated = gnn::simulate_dataset(g, options.save_dir);
  description["fingerprint"] = simulated.fingerprint;
  if (!options.save_dir.empty())
    description["saved_to"] = fs::absolute(options.save_dir).lexically_normal().string();
  if (run.resume && stored.at("fingerprint") != simulated.fingerprint)
    throw common::ConfigError(
        config, "/data/fingerprint",
        "the re-simulated data (fingerprint " + simulated.fingerprint +
            ") are not those the run was trained on (" + stored.at("fingerprint").dump() +
            "): the scene file changed, or a simulation on more than one thread (the run's was "
            "on " +
            stored.at("generation").value("threads", nlohmann::json()).dump() + ", this one on " +
            std::to_string(g.threads) +
            ") did not repeat bit for bit; resume with --data on a dataset saved by --save-data, "
            "or train on --threads 1 for bit-reproducible data");

  TrainingData data;
  data.metadata = std::move(simulated.metadata);
  data.train = std::move(simulated.train);
  data.valid = std::move(simulated.valid);
  data.description = std::move(description);
  return data;
}

}  // namespace train
