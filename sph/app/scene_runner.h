#pragma once
// Runs a scene to its end time and writes the run folder of `spill-sim run`:
//   trajectory.h5 (data contract), metadata.json, stats.json, ply/, vtk/ and png/ (optional).
// Everything is written into a hidden staging folder beside the target and renamed into place
// only when the run succeeds, so a failed or interrupted run leaves no half-written output.

#include <atomic>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>

#include "sph/core/simulation_error.h"
#include "sph/io/run_metadata.h"
#include "sph/river/spill_metrics.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/frame_loop.h"
#include "sph/simulation/simulation.h"
#include "sph/simulation/spill_measurement.h"

namespace sph {

struct RunOptions {
  std::filesystem::path out_dir;
  bool force = false;  // replace an existing out_dir
  bool ply = false;    // write PLY frames
  bool vtk = false;    // write VTK (ParaView) frames and their .pvd collection in vtk/
  bool png = false;    // write side- and top-view PNG pictures of every frame
  int threads = 1;     // recorded in stats.json (the caller sets OpenMP's thread count)
  const std::atomic<bool>* stop = nullptr;  // set from a signal handler to interrupt
  std::ostream* log = nullptr;              // progress; nullptr for silence
  bool terminal = false;                    // progress as a redrawn bar
  std::string initial_state;  // continue from this saved state (Simulation::load_state)
  double save_state_at = -1;  // save the state at this frame time to out_dir/state.h5 (>= 0)
};

// Returns the summary that stats.json holds. Throws ConfigError / SimulationError / RunInterrupted.
nlohmann::json run_scene(const LoadedScene& scene, const RunOptions& options);

// Runs a scene without writing anything and returns performance figures (for `spill-sim bench`).
nlohmann::json benchmark_scene(const LoadedScene& scene, int threads, std::ostream* log);

// The summary of a run that stats.json holds: wall time, steps, particle counts, particle-steps
// per second (steps x active fluid particles at the end / wall_s), mean solver iterations per
// step, thread count and the time split.
nlohmann::json run_summary(const Simulation& sim, double wall_s, double iterations_density,
                           double iterations_divergence, int threads);

// Where the machine and build are described in benchmark output.
nlohmann::json machine_description(int threads);

}  // namespace sph
