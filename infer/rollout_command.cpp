#include <filesystem>
#include <fstream>
#include <iomanip>
#include <numeric>
#include <sstream>

#include "common/checked_file.h"
#include "common/exit_codes.h"
#include "common/progress.h"
#include "common/stop_signals.h"
#include "gnn/eval/rollout.h"
#include "infer/commands.h"
#include "infer/loaded_data.h"
#include "infer/map_views.h"
#include "infer/trajectory_scores.h"
#include "sph/io/tensor_recorder.h"

namespace infer {
namespace fs = std::filesystem;

namespace {

// The rollout's length: to the end of the recording, or --frames, which must fit in it.
int64_t rollout_frames(const gnn::Trajectory& t, const RolloutOptions& o) {
  const int64_t available = t.frames() - 1 - o.from;
  if (o.from < 0 || available < 1)
    throw common::InputError("--from " + std::to_string(o.from) + ": " + t.source + " has " +
                             std::to_string(t.frames()) + " frames");
  if (o.frames > available)
    throw common::InputError("--frames " + std::to_string(o.frames) + ": only " +
                             std::to_string(available) + " frames follow frame " +
                             std::to_string(o.from) + " in " + t.source);
  return o.frames > 0 ? std::min<int64_t>(o.frames, available) : available;
}

// rollout.h5 (the data contract's layout) and its metadata.json.
void write_rollout_files(const fs::path& dir, const LoadedData& d, const gnn::Trajectory& t,
                         const gnn::RolloutResult& r, const RolloutOptions& o, int64_t frames) {
  sph::RecordedTrajectory rec;
  rec.time = t.time.slice(0, o.from, o.from + frames + 1).clone();
  rec.position = r.position;
  auto velocity = (r.position.slice(0, 1) - r.position.slice(0, 0, frames)) / d.metadata.frame_dt;
  rec.velocity = torch::cat({t.velocity[o.from].unsqueeze(0), velocity});
  rec.active = r.active.to(torch::kUInt8);
  rec.volume_fraction = r.oil_fraction;
  rec.particle_type = t.particle_type.to(torch::kInt32);
  rec.boundary_position = t.boundary;
  const std::string group = t.source.substr(t.source.rfind('/') + 1);
  sph::write_trajectory((dir / "rollout.h5").string(), group, rec);

  nlohmann::json metadata = d.metadata.raw;
  metadata["rollout"] = {
      {"checkpoint", o.common.checkpoint},
      {"model", d.checkpoint.simulator->model().name()},
      {"source", t.source},
      {"from_frame", o.from},
      {"frames", frames},
      {"relax_iterations", o.common.relax},
      {"sources", sources_name(sources_of(o.common.replay_recorded_sources))},
      {"note", o.common.replay_recorded_sources
                   ? "predicted positions of the learned simulator; particles enter "
                     "and leave on the recorded schedule, with their recorded oil "
                     "fraction; volume_fraction is the model's prediction for the "
                     "others"
                   : "predicted positions and oil fractions of the learned "
                     "simulator from the recorded frame from_frame on; the "
                     "dataset's scene released and retired particles"}};
  metadata["sequence_length"] = frames + 1;
  common::write_file_atomically(dir / "metadata.json", metadata.dump(2) + "\n");
}

// frames/compare_NNNN.png: truth on the left, prediction on the right, every --png-every frame.
void write_comparison_frames(const fs::path& dir, const LoadedData& d, const gnn::Trajectory& t,
                             const gnn::RolloutResult& r, const RolloutOptions& o, int64_t frames) {
  fs::create_directories(dir);
  MapViewRenderer renderer(t, d.metadata);
  for (int64_t k = 0; k <= frames; ++k) {
    if (k % std::max(o.png_every, 1) != 0 && k != frames) continue;
    std::ostringstream name;
    name << "compare_" << std::setw(4) << std::setfill('0') << (o.from + k) << ".png";
    common::write_png(
        (dir / name.str()).string(),
        image_grid({{renderer.render(t.position[o.from + k], t.active[o.from + k],
                                     t.oil_fraction[o.from + k]),
                     renderer.render(r.position[k], r.active[k], r.oil_fraction[k])}}));
  }
}

nlohmann::json rollout_timing(const gnn::Trajectory& t, const gnn::RolloutResult& r,
                              const RolloutOptions& o, int64_t frames) {
  const double wall = std::accumulate(r.frame_seconds.begin(), r.frame_seconds.end(), 0.0);
  return {{"frames", frames},
          {"threads", o.common.threads},
          {"wall_s", wall},
          {"wall_s_per_frame", wall / double(frames)},
          {"frame_seconds", r.frame_seconds},
          {"sph_seconds_per_frame", t.sph_seconds_per_frame},
          {"speedup_over_sph",
           t.sph_seconds_per_frame > 0 ? t.sph_seconds_per_frame / (wall / double(frames)) : 0.0},
          {"note",
           "wall time of the learned simulator per frame, graph building included; "
           "sph_seconds_per_frame is the SPH's time for the same frames when the dataset "
           "was generated (0 when the dataset does not record it)"}};
}

}  // namespace

void run_rollout(const RolloutOptions& o) {
  common::OutputFolder output(o.common.out_dir,
                              output_policy(o.common, {"timing.json", "metadata.json"}));
  LoadedData d = load_data(o.common);
  if (o.trajectory < 0 || o.trajectory >= int(d.trajectories.size()))
    throw common::InputError("--trajectory " + std::to_string(o.trajectory) + ": the " +
                             o.common.split + " split has " +
                             std::to_string(d.trajectories.size()) + " trajectories");
  const gnn::Trajectory& t = d.trajectories[size_t(o.trajectory)];
  const int64_t frames = rollout_frames(t, o);

  std::unique_ptr<common::ProgressReporter> progress;
  if (o.common.log)
    progress = std::make_unique<common::ProgressReporter>(*o.common.log, false, frames, "rollout");
  const auto scene = o.common.relax > 0 ? spill_scene_of(t, o.common.log) : nullptr;
  const Sources sources = sources_of(o.common.replay_recorded_sources);
  auto r = roll_out(
      *d.checkpoint.simulator, t, o.from, frames, d.metadata.frame_dt, sources,
      [&](int64_t k) {
        if (progress) progress->update(k, "");
        common::throw_if_stopped(
            o.common.stop, [&] { return "at frame " + std::to_string(k) + "; nothing written"; });
      },
      relaxation_hook(scene.get(), o.common.relax));
  if (progress) progress->finish("");

  const fs::path tmp = output.staging();
  write_rollout_files(tmp, d, t, r, o, frames);
  write_comparison_frames(tmp / "frames", d, t, r, o, frames);
  const nlohmann::json timing = rollout_timing(t, r, o, frames);
  common::write_file_atomically(tmp / "timing.json", timing.dump(2) + "\n");
  output.commit();
  if (o.common.log)
    *o.common.log << "rollout of " << frames << " frames (" << std::setprecision(3)
                  << timing["wall_s_per_frame"].get<double>() << " s per frame; SPH "
                  << t.sph_seconds_per_frame << " s) written to " << output.target().string()
                  << "\n";
}

}  // namespace infer
