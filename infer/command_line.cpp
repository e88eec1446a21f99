#include "infer/command_line.h"
#include "common/command_line.h"

namespace infer {

namespace {
const char* const kReplayHelp =
    "diagnosis only: particles enter and leave on the recording's schedule with their recorded "
    "states, as a finished SPH run supplies them (default: standalone, the dataset's scene "
    "releases and retires them)";
const char* const kVtkHelp =
    "write VTK (ParaView) point files per frame in vtk/ with a fluid.pvd collection";

// --relax: the same option, meaning and range on every command that rolls a model out.
void add_relax_option(CLI::App* c, int& relax) {
  c->add_option("--relax", relax,
                "after each learned frame, this many iterations of the simulator's "
                "constant-density correction on the predicted positions (default 0: off; at "
                "most 100)")
      ->check(common::whole_number_in(0, 100));
}

// --blas-threads beside --threads, for the commands that run one model.
void add_blas_threads_option(CLI::App* c, int& blas_threads) {
  c->add_option("--blas-threads", blas_threads,
                "OpenBLAS threads, with --threads LibTorch threads (default: the measured best "
                "split for the model)")
      ->check(common::positive());
}

void add_common(CLI::App* c, CommonOptions& o) {
  c->add_option("--checkpoint", o.checkpoint, "checkpoint (*.pt) written by spill-train")
      ->required();
  c->add_option("--data", o.data_dir, "dataset folder (metadata.json and <split>.h5)")
      ->required()
      ->check(CLI::ExistingDirectory);
  c->add_option("--split", o.split, "split to run on")
      ->check(CLI::IsMember({"train", "valid", "test"}));
  c->add_option("--out", o.out_dir, "output folder")->required();
  c->add_option("--threads", o.threads,
                "cores to use; the LibTorch/BLAS split is chosen for the model (see "
                "inference_runtime in gnn/runtime/runtime.h) unless --blas-threads is given")
      ->check(common::positive());
  add_blas_threads_option(c, o.blas_threads);
  c->add_option("--device", o.device, "where the model runs: cpu (default) or cuda[:N]");
  add_relax_option(c, o.relax);
  c->add_flag("--replay-recorded-sources", o.replay_recorded_sources, kReplayHelp);
}
}  // namespace

CLI::App* add_rollout_command(CLI::App& app, RolloutOptions& rollout) {
  auto* r = app.add_subcommand("rollout", "predict a trajectory and draw it beside the truth");
  add_common(r, rollout.common);
  r->add_option("--trajectory", rollout.trajectory, "trajectory index in the split")
      ->check(common::non_negative());
  r->add_option("--from", rollout.from, "recorded frame to start from")
      ->check(common::non_negative());
  r->add_option("--frames", rollout.frames, "frames to predict (default: to the end)")
      ->check(common::positive());
  r->add_option("--png-every", rollout.png_every, "draw every n-th frame")
      ->check(common::positive());
  r->add_flag("--vtk", rollout.vtk, kVtkHelp);
  return r;
}

CLI::App* add_eval_command(CLI::App& app, EvalOptions& eval) {
  auto* e = app.add_subcommand("eval", "accuracy and speed over every trajectory of a split");
  add_common(e, eval.common);
  e->add_option("--from", eval.from, "recorded frame each rollout starts from")
      ->check(common::non_negative());
  e->add_option("--frames", eval.frames, "frames per rollout (default: to the end)")
      ->check(common::positive());
  return e;
}

CLI::App* add_compare_command(CLI::App& app, CompareOptions& compare) {
  auto* c = app.add_subcommand(
      "compare", "several models (and the constant-velocity floor) on the same trajectories");
  c->add_option("--checkpoints", compare.checkpoints, "checkpoints (*.pt) written by spill-train")
      ->check(CLI::ExistingFile);
  c->add_flag("--constant-velocity", compare.constant_velocity,
              "add the constant-velocity floor (every particle keeps its last velocity)");
  c->add_option("--ceiling", compare.ceiling_jitter,
                "add the ceiling: the dataset's own simulator run again from the same frame with "
                "every position jittered by up to this many particle diameters (e.g. 0.001); "
                "standalone only")
      ->check(common::positive());
  c->add_option("--members", compare.members,
                "ensemble members per model and trajectory: each starts from the frame jittered "
                "with its own seed (the same seeds for every model); scored by fair CRPS and "
                "Brier scores besides the members' mean scores; standalone only")
      ->check(CLI::Range(1, 1000));
  c->add_option("--member-jitter", compare.member_jitter,
                "the members' jitter, in particle diameters (default 0.001)")
      ->check(common::positive());
  c->add_option("--data", compare.data_dir, "dataset folder (metadata.json and <split>.h5)")
      ->required()
      ->check(CLI::ExistingDirectory);
  c->add_option("--split", compare.split, "split to run on")
      ->check(CLI::IsMember({"train", "valid", "test"}));
  c->add_option("--out", compare.out_dir, "output folder")->required();
  c->add_option("--from", compare.from, "recorded frame each rollout starts from")
      ->check(common::non_negative());
  c->add_option("--frames", compare.frames, "frames per rollout (default: to the end)")
      ->check(common::positive());
  c->add_option("--threads", compare.threads,
                "cores to use; each model gets its measured best LibTorch/BLAS split unless "
                "--blas-threads is given")
      ->check(common::positive());
  c->add_option("--blas-threads", compare.blas_threads, "OpenBLAS threads for every model")
      ->check(common::positive());
  c->add_option("--device", compare.device, "where the models run: cpu (default) or cuda[:N]");
  add_relax_option(c, compare.relax);
  c->add_flag("--replay-recorded-sources", compare.replay_recorded_sources, kReplayHelp);
  return c;
}

CLI::App* add_predict_command(CLI::App& app, PredictOptions& o) {
  auto* p = app.add_subcommand(
      "predict",
      "forecast a scene with a learned simulator, no recording needed: the scene's own sources "
      "and sinks release and retire particles; writes the run folder of spill-sim run");
  p->add_option("--checkpoint", o.checkpoint, "checkpoint (*.pt) written by spill-train")
      ->required()
      ->check(CLI::ExistingFile);
  p->add_option("--scene", o.scene_file, "scene JSON file")->required();
  p->add_option("--out", o.out_dir, "output folder (an earlier run folder is replaced)")
      ->required();
  p->add_option("--set", o.overrides, "override a scene value: /json/pointer=value");
  p->add_option("--initial-state", o.initial_state,
                "start from a state saved by spill-sim run --save-state-at (e.g. a warmed-up "
                "river)")
      ->check(CLI::ExistingFile);
  p->add_option("--end-time", o.end_time, "end of the forecast (s; default: the scene's)")
      ->check(common::positive());
  p->add_flag("--png", o.png, "write side-, top- and river-view pictures of every frame");
  p->add_flag("--vtk", o.vtk, kVtkHelp);
  add_relax_option(p, o.relax);
  p->add_option("--members", o.members,
                "an ensemble of K forecasts in one process: the first as without it, the others "
                "from a start jittered by --member-jitter; adds ensemble.json (per frame the "
                "mean and 10/50/90 % quantiles of front, slick area, centroid and watch-point "
                "arrival), members/NN/spill.json and oiling.png (default 1)")
      ->check(common::positive());
  p->add_option("--member-jitter", o.member_jitter,
                "the members' jitter, in particle diameters (default 0.001)")
      ->check(common::positive());
  p->add_option("--threads", o.threads, "cores to use (default 2)")->check(common::positive());
  add_blas_threads_option(p, o.blas_threads);
  return p;
}

CLI::App* add_export_command(CLI::App& app, ExportOptions& o) {
  auto* x = app.add_subcommand(
      "export", "a weights-only copy of a checkpoint (no optimiser state), to share or commit");
  x->add_option("--checkpoint", o.from, "checkpoint (*.pt) written by spill-train")
      ->required()
      ->check(CLI::ExistingFile);
  x->add_option("--out", o.to, "the copy (*.pt); training cannot resume from it")->required();
  x->add_flag("--force", o.force,
              "replace an existing --out, only if it is itself a checkpoint (atomically)");
  return x;
}

}  // namespace infer
