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

#include <array>
#include <atomic>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace sph {

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
  std::ostream* log = nullptr;
};

// Trajectories per split: the fractions of `total` rounded, every split with a non-zero fraction
// getting at least one. Throws common::InputError when that is impossible or the fractions
// do not sum to 1.
std::array<int, 3> split_counts(int total, const std::array<double, 3>& fractions);

// Returns metadata.json's content. Throws ConfigError for a bad scene or pointer,
// SimulationError for a failed run, RunInterrupted (scene_runner.h) when `stop` was set.
nlohmann::json generate_dataset(const GenerateOptions& options);

}  // namespace sph
