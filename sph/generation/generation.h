#pragma once
// The dataset generation pipeline: one request (a scene, parameter ranges drawn per trajectory,
// a seed, splits, frames, a warm-up) simulated trajectory by trajectory into a TrajectorySink,
// then the normalisation statistics and metadata.json of the whole:
//   plan -> simulate each trajectory into the sink -> statistics -> metadata -> the sink's splits.
// `spill-sim generate` writes a dataset folder through it (dataset_folder.h: HDF5 parts, resumed
// after an interruption, assembled into train.h5, valid.h5 and test.h5); `spill-train --scene`
// records the same trajectories into tensors in-process (gnn/data/simulated_dataset.h). Both
// get the same draws, warm-up rule, statistics and metadata (docs/design.md's data contract).
// Parameters are all drawn from the seed before anything runs, so a resumed or repeated
// generation draws the same ones; on one thread the data are bit-identical. The same request can
// be cut into shards (a cluster's job array): shard I of N simulates the trajectories i with
// i mod N = I, and the statistics, summed over the trajectories in index order, do not depend on
// the cut.

#include <array>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace sph {

class Simulation;

// "/json/pointer=LO:HI": the value is drawn uniformly from [LO, HI] for every trajectory.
struct ParameterRange {
  std::string pointer;
  double lo = 0, hi = 0;
};
// Parses "/pointer=LO:HI"; throws common::InputError with the text on a malformed one.
ParameterRange parse_parameter_range(const std::string& text);

// Which share of a generation's trajectories one process simulates.
struct GenerationShard {
  int index = 0, count = 1;    // trajectories i with i mod count == index
  bool assemble_only = false;  // simulate none: assemble what the shards finished
};
// Parses --shard "I/N"; throws common::InputError naming it unless 0 <= I < N.
GenerationShard parse_shard(const std::string& text);

struct GenerateOptions {
  std::string scene_file;
  std::vector<std::string> overrides;  // --set, applied before the drawn parameters
  int trajectories = 1;
  std::filesystem::path out_dir;  // the dataset folder (dataset_folder.h); unused by other sinks
  std::vector<ParameterRange> vary;
  std::uint64_t seed = 0;
  std::array<double, 3> split = {0.8, 0.1, 0.1};  // train, valid, test
  int frames = 0;       // recorded frames per trajectory after the warm-up; 0: to the end
  double warm_up = -1;  // s before recording starts; < 0: the earliest leak's start (or 0)
  int threads = 1;      // recorded in the metadata (the caller sets OpenMP's thread count)
  GenerationShard shard;
  const std::atomic<bool>* stop = nullptr;
  std::ostream* log = nullptr;  // progress per trajectory; null for none
};

// Parses --split "TRAIN/VALID/TEST" (e.g. "0.8/0.1/0.1"); throws common::InputError naming it.
std::array<double, 3> parse_split(const std::string& text);

// Trajectories per split: the fractions of `total` rounded, every split with a non-zero fraction
// getting at least one. Throws common::InputError when that is impossible or the fractions
// do not sum to 1.
std::array<int, 3> split_counts(int total, const std::array<double, 3>& fractions);

// "train", "valid", "test" for split 0, 1, 2.
const char* split_name(int split);
// A trajectory's number as its group and part files name it: 00000, 00001, ...
std::string group_name(int index);

// The request's settings as metadata.json's "generation" holds them: seed, trajectories, split,
// frames, warm_up, vary, overrides and threads.
nlohmann::json generation_settings(const GenerateOptions& options);

// One trajectory of a generation.
struct TrajectoryPlan {
  int index = 0;
  int split = 0;              // 0 train, 1 valid, 2 test (split_counts, in index order)
  nlohmann::json parameters;  // {pointer: drawn value}
};

// Where the pipeline puts the trajectories it simulates.
class TrajectorySink {
 public:
  virtual ~TrajectorySink() = default;
  // Once, with the whole plan, before any trajectory (a dataset folder checks the request here).
  virtual void start(const GenerateOptions& /*options*/,
                     const std::vector<TrajectoryPlan>& /*plan*/) {}
  // The description of a trajectory an earlier, interrupted generation finished, if the sink
  // holds one: it is then not simulated again.
  virtual std::optional<nlohmann::json> finished_before(const TrajectoryPlan& /*plan*/) {
    return std::nullopt;
  }
  // What an interruption message adds about the trajectory being simulated.
  virtual std::string interrupted_note(const TrajectoryPlan& plan) const = 0;
  // Once per trajectory with the simulation as built, before it runs (particle types are taken
  // here: the mixture model changes a particle's type later).
  virtual void begin(const Simulation& sim, const TrajectoryPlan& plan) = 0;
  // Each recorded frame in order, the first included; particles in identity order are
  // sim.in_id_order(...).
  virtual void record(const Simulation& sim) = 0;
  // After the trajectory's last frame, with its description; abandon() instead when its
  // simulation failed or was interrupted.
  virtual void end(const TrajectoryPlan& plan, const nlohmann::json& description) = 0;
  virtual void abandon(const TrajectoryPlan& /*plan*/) {}
  // Once, after every trajectory, with metadata.json's content.
  virtual void finish(const std::vector<TrajectoryPlan>& /*plan*/,
                      const nlohmann::json& /*metadata*/) {}
};

// What a generation, or one shard of it, ended with.
struct GenerationResult {
  // metadata.json's content; null while trajectories of other shards are missing.
  nlohmann::json metadata;
  std::vector<int> missing;  // trajectories not finished yet (other shards'), by index
  int simulated = 0;         // trajectories this call simulated
};

// Runs the request's (or its shard's) trajectories into `sink`; when every trajectory of the
// request is then finished (the sink holds those of other shards), computes the metadata and
// lets the sink assemble the whole. Bad input (scene file, --vary pointer, counts) throws
// common::InputError or ConfigError before anything is simulated; a failed run throws
// SimulationError, a stop request RunInterrupted.
GenerationResult generate(const GenerateOptions& options, TrajectorySink& sink);

}  // namespace sph
