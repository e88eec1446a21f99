#pragma once
// The subcommands of spill-infer.

#include <atomic>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace infer {

struct CommonOptions {
  std::string checkpoint;
  std::string data_dir;
  std::string split = "test";
  std::string out_dir;
  std::ostream* log = nullptr;
  int threads = 2;
  int blas_threads = 0;        // 0: the measured best split for the model (gnn::inference_runtime)
  std::string device = "cpu";  // where the model runs; the data pipeline stays on the CPU
  int relax = 0;               // iterations of the SPH density correction after each learned frame
  // Diagnosis: particles enter and leave on the recording's schedule, with recorded states,
  // instead of from the dataset's scene (--replay-recorded-sources).
  bool replay_recorded_sources = false;
  // Set by Ctrl-C or SIGTERM (common/stop_signals.h): stop at the next frame, writing nothing.
  const std::atomic<bool>* stop = nullptr;
};

struct RolloutOptions {
  CommonOptions common;
  int trajectory = 0;
  int from = 5;
  int frames = 0;  // 0 = to the end of the recording
  int png_every = 5;
  bool vtk = false;  // the predicted frames as VTK (ParaView) point files in OUT/vtk/
};

struct EvalOptions {
  CommonOptions common;
  int from = 5;
  int frames = 0;  // 0 = to the end of each recording
};

// Several models (checkpoints and, on request, the built-in constant-velocity floor) on the same
// trajectories.
struct CompareOptions {
  std::vector<std::string> checkpoints;
  bool constant_velocity = false;
  // > 0: add the ceiling, the data's own simulator run again from the starting frame with the
  // positions jittered by this many particle diameters (gnn/eval/solver_rollout.h)
  double ceiling_jitter = 0;
  // Ensembles (issue 48): every model, the floor and the ceiling run `members` times per
  // trajectory, each member from the starting frame jittered by up to member_jitter particle
  // diameters with its own seed (the same seeds for every model); 1: one run, learned models
  // unjittered.
  int members = 1;
  double member_jitter = 0.001;
  std::string data_dir;
  std::string split = "test";
  std::string out_dir;
  int from = 5;
  int frames = 0;  // 0 = to the end of each recording
  int threads = 2;
  int blas_threads = 0;  // 0: the measured best split for each model
  std::string device = "cpu";
  int relax = 0;  // iterations of the SPH density correction after each learned frame
  bool replay_recorded_sources = false;  // as CommonOptions's
  std::ostream* log = nullptr;
  const std::atomic<bool>* stop = nullptr;  // as CommonOptions::stop
};

// A forecast from a scene alone: the learned simulator moves the particles, the scene's own
// sources and sinks release and retire them (gnn/eval/scene_rollout.h).
struct PredictOptions {
  std::string checkpoint;
  std::string scene_file;
  std::vector<std::string> overrides;  // --set /pointer=value
  std::string initial_state;           // a state saved by spill-sim run --save-state-at
  double end_time = -1;                // > 0: the scene's /end_time replaced
  std::string out_dir;
  bool png = false;
  bool vtk = false;  // VTK (ParaView) point files of every frame in OUT/vtk/
  int relax = 0;
  // An ensemble (issue 48): K forecasts, the first unperturbed (this folder's), the others with
  // every active particle's start moved by up to member_jitter particle diameters (seeded by the
  // member's number), summarised in ensemble.json, members/ and oiling.png.
  int members = 1;
  double member_jitter = 0.001;
  int threads = 2;
  int blas_threads = 0;
  std::ostream* log = nullptr;
  bool terminal = false;                    // progress as a redrawn bar
  const std::atomic<bool>* stop = nullptr;  // as CommonOptions::stop
};

// The run folder of `spill-sim run` (metadata.json naming the checkpoint, trajectory.h5,
// stats.json, spill.json and spill.svg, png/ and vtk/ on request) from the model instead of the
// solver. Returns stats.json's summary.
nlohmann::json run_predict(const PredictOptions& options);

// Predicted trajectory in the data contract (OUT/rollout.h5, OUT/metadata.json), side-by-side
// top views (OUT/frames/), timing against the SPH (OUT/timing.json), and on request VTK point
// files of the predicted frames (OUT/vtk/).
void run_rollout(const RolloutOptions& options);

// Accuracy and speed over every trajectory of a split: OUT/eval.json and OUT/error_vs_horizon.svg.
void run_eval(const EvalOptions& options);

// OUT/comparison.json, OUT/comparison.md and OUT/comparison.png (rows: the simulator, then each
// model; columns: six moments of the first trajectory); OUT/teacher_student.md as well when the
// models include a teacher and a student (teacher_student_table.h).
void run_compare(const CompareOptions& options);

}  // namespace infer
