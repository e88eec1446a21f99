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
#include "sph/io/vtk_writer.h"

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

// [F + 1, N, 3] m/s: the recorded velocity at the start, then each frame's displacement over
// the frame interval.
torch::Tensor rollout_velocity(const LoadedData& d, const gnn::Trajectory& t,
                               const gnn::RolloutResult& r, const RolloutOptions& o,
                               int64_t frames) {
  auto velocity = (r.position.slice(0, 1) - r.position.slice(0, 0, frames)) / d.metadata.frame_dt;
  return torch::cat({t.velocity[o.from].unsqueeze(0), velocity});
}

// rollout.h5 (the data contract's layout) and its metadata.json.
void write_rollout_files(const fs::path& dir, const LoadedData& d, const gnn::Trajectory& t,
                         const gnn::RolloutResult& r, const RolloutOptions& o, int64_t frames) {
  sph::RecordedTrajectory rec;
  rec.time = t.time.slice(0, o.from, o.from + frames + 1).clone();
  rec.position = r.position;
  rec.velocity = rollout_velocity(d, t, r, o, frames);
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

// [N, 3] rows as vectors.
std::vector<sph::Vec3> vectors_of(const torch::Tensor& rows) {
  const torch::Tensor x = rows.to(torch::kFloat64).contiguous();
  TORCH_CHECK(x.dim() == 2 && x.size(1) == 3, "vectors_of: expected [N, 3], got ", x.sizes());
  const auto a = x.accessor<double, 2>();
  std::vector<sph::Vec3> out(size_t(x.size(0)));
  for (int64_t i = 0; i < x.size(0); ++i)
    out[size_t(i)] = sph::Vec3(sph::Real(a[i][0]), sph::Real(a[i][1]), sph::Real(a[i][2]));
  return out;
}

// vtk/: boundary.vtp, a fluid_NNNNN.vtp per frame (numbered as in the recording, every particle
// in identity order with its predicted position, velocity and oil fraction, its type by the one
// oil rule, and whether it is active) and fluid.pvd with the recorded times. A learned frame has
// no density or pressure: those arrays are left out.
void write_vtk_frames(const fs::path& dir, const LoadedData& d, const gnn::Trajectory& t,
                      const gnn::RolloutResult& r, const RolloutOptions& o, int64_t frames) {
  fs::create_directories(dir);
  sph::VtkPoints boundary;
  boundary.position = vectors_of(t.boundary);
  boundary.type.assign(boundary.position.size(), std::int32_t(sph::ParticleType::kBoundary));
  sph::write_vtp(dir / "boundary.vtp", boundary);

  const torch::Tensor velocity = rollout_velocity(d, t, r, o, frames);
  const torch::Tensor oil = r.oil_fraction.to(torch::kFloat64).contiguous();  // [F + 1, N]
  const torch::Tensor active = r.active.to(torch::kUInt8).contiguous();       // [F + 1, N]
  const torch::Tensor time = t.time.to(torch::kFloat64).contiguous();         // [T]
  sph::VtkSeries series(dir, "fluid.pvd");
  for (int64_t k = 0; k <= frames; ++k) {
    sph::VtkPoints p;
    p.position = vectors_of(r.position[k]);
    p.velocity = vectors_of(velocity[k]);
    const torch::Tensor oil_k = oil[k], active_k = active[k];  // [N]
    const auto fraction = oil_k.accessor<double, 1>();
    const auto on = active_k.accessor<std::uint8_t, 1>();
    for (int64_t i = 0; i < fraction.size(0); ++i) {
      p.oil_fraction.push_back(sph::Real(fraction[i]));
      const bool oil_now = sph::is_oil(sph::Real(fraction[i]));
      p.type.push_back(std::int32_t(oil_now ? sph::ParticleType::kOil : sph::ParticleType::kWater));
      p.active.push_back(on[i]);
    }
    std::ostringstream name;
    name << "fluid_" << std::setw(5) << std::setfill('0') << (o.from + k) << ".vtp";
    series.add_frame(name.str(), time[o.from + k].item<double>(), p);
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
  if (o.vtk) write_vtk_frames(tmp / "vtk", d, t, r, o, frames);
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
