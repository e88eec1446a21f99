#pragma once
// `spill-sim compare`: one scene run with each of several pressure solvers up to a few moments,
// the MTDF-SPH paper's Table 3 and Fig. 10 from one command. Writes into one output folder:
//   table.json  per solver: wall time to each moment, particle-steps per second, mean pressure
//               iterations per step, final mean density error, fluid particles and, for a leak
//               in a river, the largest slick area, the furthest front and the first bank
//               contacts over the run (sph/river/spill_metrics.h);
//   table.md    the same as a Markdown table, with the scene, frame_dt, threads and machine;
//   views.png   one column per solver, one row per moment, each cell the river's map view (the
//               top view without terrain); oil is a particle with oil fraction >= 0.5.
// A solver whose run fails (SimulationError, or any other std::exception; not an interruption)
// is recorded with the frame and the reason, its cells from that moment on are left grey, and
// the other solvers still run. Only when every solver fails is it an error, and then nothing is
// written. The folder appears whole or not at all (common/output_folder.h).

#include <atomic>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace sph {

struct SolverTableRequest {
  std::string scene_file;
  std::vector<std::string> overrides;  // applied to every run, before "/solver=NAME"
  std::vector<std::string> solvers;    // registered names, each once, in column order
  // The moments, in frames of the scene's output/frame_dt: increasing, >= 1, within the scene's
  // end_time. Every solver runs to the last.
  std::vector<int> frames;
  std::filesystem::path out_dir;
  bool force = false;    // replace an earlier compare folder (one holding table.json, ...)
  int threads = 1;       // recorded (the caller sets OpenMP's thread count)
  int cell_width = 240;  // pixels across one view of views.png
  const std::atomic<bool>* stop = nullptr;  // set from a signal handler to interrupt
  std::ostream* log = nullptr;              // progress; nullptr for silence
  bool terminal = false;                    // progress as a redrawn bar
};

// Runs the solvers one after the other and writes the folder; returns table.json's content.
// Throws common::InputError for a bad request, scene or output folder before anything runs,
// SimulationError naming every solver's failure when all of them failed, RunInterrupted when
// stopped (nothing written in either case).
nlohmann::json write_solver_table(const SolverTableRequest& request);

// table.md from table.json's content.
std::string solver_table_markdown(const nlohmann::json& table);

}  // namespace sph
