#pragma once
// `spill-sim generate`: simulates N trajectories of a scene with parameters drawn from given
// ranges and writes a dataset in the data contract (DESIGN.md): train.h5, valid.h5, test.h5 (one
// group per trajectory, "00000", "00001", ... within each file) and metadata.json (the keys of a
// run's metadata plus the normalisation statistics over the training split, sequence lengths and
// counts per split, and every trajectory's drawn parameters).
//
// Each trajectory is first written to parts/ (its HDF5 file and a JSON of its parameters and
// statistics, each renamed into place when complete), so an interrupted generation resumes
// without redoing finished trajectories; the split files are assembled from the parts at the end.
// Parameters are all drawn from the seed before anything runs, so a resumed or repeated
// generation draws the same ones; on one thread the data are bit-identical.
//
// The pieces (plan_trajectories, simulate_trajectory, dataset_metadata, assemble_split) are public
// so that `spill-train --scene` simulates the same trajectories into tensors in-process
// (gnn/data/simulated_dataset.h) with the same draws, warm-up, statistics and metadata.

#include <array>
#include <atomic>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "sph/scene/scene_loader.h"

namespace sph {

class Simulation;

// "/json/pointer=LO:HI": the value is drawn uniformly from [LO, HI] for every trajectory.
struct ParameterRange {
  std::string pointer;
  double lo = 0, hi = 0;
};
// Parses "/pointer=LO:HI"; throws common::InputError with the text on a malformed one.
ParameterRange parse_parameter_range(const std::string& text);

struct GenerateOptions {
  std::string scene_file;
  std::vector<std::string> overrides;  // --set, applied before the drawn parameters
  int trajectories = 1;
  std::filesystem::path out_dir;
  std::vector<ParameterRange> vary;
  std::uint64_t seed = 0;
  std::array<double, 3> split = {0.8, 0.1, 0.1};  // train, valid, test
  int frames = 0;       // recorded frames per trajectory after the warm-up; 0: to the end
  double warm_up = -1;  // s before recording starts; < 0: the earliest leak's start (or 0)
  int threads = 1;      // recorded in the metadata (the caller sets OpenMP's thread count)
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

// One trajectory of a generation.
struct TrajectoryPlan {
  int index = 0;
  int split = 0;              // 0 train, 1 valid, 2 test (split_counts, in index order)
  nlohmann::json parameters;  // {pointer: drawn value}
};

// Checks the request, draws every trajectory's parameters from the seed (all before anything
// runs, so a resumed or repeated generation draws the same ones) and assigns the splits. Loads
// every drawn scene, so a missing scene file or a bad pointer throws ConfigError (naming the file
// and the pointer) before anything is simulated or written. Throws common::InputError for bad
// counts.
std::vector<TrajectoryPlan> plan_trajectories(const GenerateOptions& options);

// The scene of one trajectory: the scene file with options.overrides, then the drawn parameters.
LoadedScene trajectory_scene(const GenerateOptions& options, const nlohmann::json& parameters);

// Where simulate_trajectory hands the frames it records.
class TrajectorySink {
 public:
  virtual ~TrajectorySink() = default;
  // Once, with the simulation as built, before it runs (particle types are taken here: the
  // mixture model changes a particle's type later).
  virtual void begin(const Simulation& sim) = 0;
  // Each recorded frame in order, the first included; particles in identity order are
  // sim.in_id_order(...).
  virtual void record(const Simulation& sim) = 0;
};

// Simulates one planned trajectory with subnormals flushed (floating_point.h, as spill-sim does)
// and hands its recorded frames to `sink`: from the warm-up (options.warm_up, or the earliest
// leak's start when < 0) for options.frames frames (to the scene's end when 0). Returns its
// description: index, split, parameters, particles, frames, first_frame_time, sph_wall_s,
// sph_seconds_per_frame, simulation_threads (the fewest OpenMP threads a frame began with), and
// velocity_moments and acceleration_moments (the sums behind the normalisation statistics).
// `interrupted_note` is added to the message when options.stop interrupts it (RunInterrupted).
nlohmann::json simulate_trajectory(const GenerateOptions& options, const TrajectoryPlan& plan,
                                   TrajectorySink& sink, const std::string& interrupted_note);

// The request's settings as metadata.json's "generation" holds them: seed, trajectories, split,
// frames, warm_up, vary, overrides and threads.
nlohmann::json generation_settings(const GenerateOptions& options);

// metadata.json of a dataset from the descriptions simulate_trajectory returned for every
// trajectory, in index order: the run metadata of the first trajectory's scene, sequence lengths
// and counts per split, the normalisation statistics over the training split (every trajectory
// when it is empty), the generation settings, and each trajectory's description without its
// moments and with its group in its split's file.
nlohmann::json dataset_metadata(const GenerateOptions& options,
                                const std::vector<nlohmann::json>& trajectories);

// Writes a split file holding group "00000" of each of `parts` as groups 00000, 00001, ... in
// order, atomically (temp file + rename). Throws SimulationError naming the file.
void assemble_split(const std::filesystem::path& file,
                    const std::vector<std::filesystem::path>& parts);

// Returns metadata.json's content. Throws ConfigError for a bad scene or pointer,
// SimulationError for a failed run, RunInterrupted (scene_runner.h) when `stop` was set.
nlohmann::json generate_dataset(const GenerateOptions& options);

}  // namespace sph
