#include "gnn/eval/scene_rollout.h"

#include <chrono>
#include <random>
#include <stdexcept>

#include "common/config_error.h"
#include "gnn/data/frame_window.h"
#include "gnn/eval/spill_measures.h"
#include "sph/scene/scene_loader.h"

namespace gnn {

namespace {

// The active particles in the simulation's slot order.
struct ActiveParticles {
  torch::Tensor ids;                               // [n] int64
  torch::Tensor position, velocity, oil_fraction;  // [n, 3], [n, 3], [n] float32
};

ActiveParticles active_particles(const sph::Simulation& sim) {
  const sph::FluidParticles& f = sim.fluid();
  const int64_t n = int64_t(f.active_count());
  ActiveParticles a{torch::empty({n}, torch::kInt64), torch::empty({n, 3}), torch::empty({n, 3}),
                    torch::empty({n})};
  auto ids = a.ids.accessor<int64_t, 1>();
  auto x = a.position.accessor<float, 2>();
  auto v = a.velocity.accessor<float, 2>();
  auto alpha = a.oil_fraction.accessor<float, 1>();
  for (int64_t i = 0; i < n; ++i) {
    ids[i] = int64_t(f.id[size_t(i)]);
    for (int d = 0; d < 3; ++d) {
      x[i][d] = float(f.position[size_t(i)][d]);
      v[i][d] = float(f.velocity[size_t(i)][d]);
    }
    alpha[i] = float(f.oil_fraction[size_t(i)]);
  }
  return a;
}

}  // namespace

SceneRollout::SceneRollout(LearnedSimulator& model, sph::Simulation& simulation,
                           torch::Tensor material, double frame_dt, std::string where)
    : model_(model),
      sim_(simulation),
      material_(std::move(material)),
      boundary_(tensor_of(simulation.boundary().position)),
      where_(std::move(where)),
      frame_dt_(frame_dt),
      start_time_(simulation.time()),
      history_(torch::zeros({int64_t(simulation.fluid().size()), kWindow, 3})),
      current_(torch::zeros({int64_t(simulation.fluid().size())}, torch::kBool)) {}

void SceneRollout::set_history(const torch::Tensor& ids, const torch::Tensor& history) {
  history_.index_copy_(0, ids, history);
  current_.index_fill_(0, ids, true);
}

sph::ExternalFrameStats SceneRollout::advance(int frame, const FrameCorrection& correct) {
  torch::NoGradGuard no_grad;
  // What is due by the start (the rest is released at the end of each frame below).
  if (frames_ == 0) sim_.release_sources();
  const ActiveParticles now = active_particles(sim_);
  launch_fresh(now.ids, now.position, now.velocity);
  auto window = history_.index_select(0, now.ids);
  NextState next = model_.next_state({window, now.oil_fraction, material_, boundary_});
  // Named here, with the frame: later it would surface as a particle outside the domain.
  if (!torch::isfinite(next.position).all().item<bool>())
    throw std::runtime_error(where_ + ": the model diverged at frame " + std::to_string(frame) +
                             ": a predicted position is not finite");
  if (correct) correct(next.position, next.oil_fraction);
  ++frames_;
  const sph::ExternalFrameStats stats =
      sim_.apply_external_frame(start_time_ + double(frames_) * frame_dt_,
                                vectors_of(next.position), reals_of(next.oil_fraction), frame);
  retired_.retired += stats.retired;
  retired_.left_domain += stats.left_domain;
  // Shift every window; the newest position is where the simulation has the particle (the
  // river's buffers may have moved it).
  history_.index_copy_(0, now.ids, torch::cat({window.slice(1, 1), next.position.unsqueeze(1)}, 1));
  const ActiveParticles after = active_particles(sim_);
  current_.fill_(false);
  current_.index_fill_(0, after.ids, true);
  history_.select(1, kWindow - 1).index_copy_(0, after.ids, after.position);
  // Released at the frame's end where they would be by now (as a solver run releases them during
  // the frame): the model moves them from the next frame on, with a launched history.
  sim_.release_sources();
  return stats;
}

void SceneRollout::launch_fresh(const torch::Tensor& ids, const torch::Tensor& position,
                                const torch::Tensor& velocity) {
  // Particles new to the run (just released, or active at its start without a history).
  const auto in_slots = (~current_.index_select(0, ids)).nonzero().view(-1);
  if (in_slots.size(0) == 0) return;
  const auto fresh = ids.index_select(0, in_slots);
  history_.index_copy_(0, fresh,
                       launched_histories(position.index_select(0, in_slots),
                                          velocity.index_select(0, in_slots), frame_dt_));
  current_.index_fill_(0, fresh, true);
}

void SceneRollout::jitter_start(double jitter, uint64_t seed) {
  if (frames_ != 0) throw std::logic_error(where_ + ": an ensemble member jitters its start only");
  sim_.release_sources();
  const ActiveParticles now = active_particles(sim_);
  launch_fresh(now.ids, now.position, now.velocity);
  std::vector<std::uint8_t> active(size_t(history_.size(0)), 0);
  auto ids = now.ids.accessor<int64_t, 1>();
  for (int64_t i = 0; i < ids.size(0); ++i) active[size_t(ids[i])] = 1;
  history_ += jitter_offsets(active, jitter, seed).unsqueeze(1);
}

torch::Tensor jitter_offsets(const std::vector<std::uint8_t>& active, double jitter,
                             uint64_t seed) {
  if (!(jitter >= 0)) throw std::invalid_argument("jitter must be >= 0");
  auto offset = torch::zeros({int64_t(active.size()), 3});
  if (jitter == 0) return offset;
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(-jitter, jitter);
  auto o = offset.accessor<float, 2>();
  for (size_t i = 0; i < active.size(); ++i)
    if (active[i])
      for (int d = 0; d < 3; ++d) o[int64_t(i)][d] = float(sph::Real(uniform(random)));
  return offset;
}

torch::Tensor jitter_active_positions(sph::RecordedFrame& f, double jitter, uint64_t seed) {
  const torch::Tensor offset = jitter_offsets(f.active, jitter, seed);
  auto o = offset.accessor<float, 2>();
  for (size_t i = 0; i < f.position.size(); ++i)
    if (f.active[i])
      for (int d = 0; d < 3; ++d) f.position[i][d] += sph::Real(o[int64_t(i)][d]);
  return offset;
}

IdentityFrame identity_frame(const sph::Simulation& sim) {
  const sph::FluidParticles& f = sim.fluid();
  const int64_t n = int64_t(f.size());
  IdentityFrame out{torch::empty({n, 3}), torch::zeros({n}, torch::kBool), torch::empty({n})};
  auto x = out.position.accessor<float, 2>();
  auto active = out.active.accessor<bool, 1>();
  auto alpha = out.oil_fraction.accessor<float, 1>();
  for (int64_t i = 0; i < n; ++i) {
    const int64_t id = int64_t(f.id[size_t(i)]);
    for (int d = 0; d < 3; ++d) x[id][d] = float(f.position[size_t(i)][d]);
    active[id] = i < int64_t(f.active_count());
    alpha[id] = float(f.oil_fraction[size_t(i)]);
  }
  return out;
}

namespace {

sph::RecordedFrame recorded_frame(const Trajectory& t, int64_t frame) {
  sph::RecordedFrame r;
  r.time = t.time[frame].item<double>();
  r.position = vectors_of(t.position[frame]);
  r.velocity = vectors_of(t.velocity[frame]);
  r.oil_fraction = reals_of(t.oil_fraction[frame]);
  const auto active = t.active[frame].to(torch::kUInt8).contiguous();
  r.active.assign(active.data_ptr<uint8_t>(), active.data_ptr<uint8_t>() + active.numel());
  return r;
}

}  // namespace

std::unique_ptr<sph::Simulation> simulation_at_frame(
    const Trajectory& t, int64_t frame, double frame_dt,
    const std::function<void(sph::RecordedFrame&)>& adjust) {
  if (!t.scene.is_object() || t.scene.empty())
    throw DatasetError(
        t.source +
        ": the dataset's metadata.json has no \"scene\" to roll out standalone "
        "(its sources and sinks); --replay-recorded-sources replays the recording's");
  sph::SceneConfig scene;
  try {
    scene = sph::parse_scene(t.scene, t.source + " (the dataset's scene)").config;
  } catch (const common::ConfigError& e) {
    throw DatasetError(std::string(e.what()) +
                       ": no scene to roll out standalone from (its sources and sinks); "
                       "--replay-recorded-sources replays the recording's");
  }
  auto sim = std::make_unique<sph::Simulation>(scene);
  if (int64_t(sim->fluid().size()) != t.particles())
    throw DatasetError(t.source + ": the dataset's scene makes " +
                       std::to_string(sim->fluid().size()) + " particles, the trajectory has " +
                       std::to_string(t.particles()));
  sph::RecordedFrame recorded = recorded_frame(t, frame);
  if (adjust) adjust(recorded);
  sim->restore_recorded_frame(recorded, frame_dt);
  return sim;
}

RestartedRollout restart_rollout(const Trajectory& t, int64_t first_frame, int64_t frames,
                                 double frame_dt, double jitter, uint64_t seed) {
  if (first_frame < 0 || frames < 1 || first_frame + frames >= t.frames())
    throw std::invalid_argument(t.source + ": cannot roll out " + std::to_string(frames) +
                                " frames from frame " + std::to_string(first_frame) + " of " +
                                std::to_string(t.frames()));
  RestartedRollout r;
  r.simulation = simulation_at_frame(t, first_frame, frame_dt, [&](sph::RecordedFrame& f) {
    r.offset = jitter_active_positions(f, jitter, seed);
  });
  RolloutResult& out = r.result;
  out.first_frame = first_frame;
  out.position = torch::empty({frames + 1, t.particles(), 3});
  out.active = torch::empty({frames + 1, t.particles()}, torch::kBool);
  out.oil_fraction = torch::empty({frames + 1, t.particles()});
  out.position[0] = t.position[first_frame];
  out.active[0] = t.active[first_frame];
  out.oil_fraction[0] = t.oil_fraction[first_frame];
  return r;
}

void record_frames(RestartedRollout& rollout, const std::function<void(int64_t)>& advance,
                   const std::function<void(int64_t)>& on_frame) {
  RolloutResult& out = rollout.result;
  const int64_t frames = out.position.size(0) - 1;
  for (int64_t k = 1; k <= frames; ++k) {
    const auto start = std::chrono::steady_clock::now();
    advance(k);
    const IdentityFrame f = identity_frame(*rollout.simulation);
    out.position[k] = f.position;
    out.active[k] = f.active;
    out.oil_fraction[k] = f.oil_fraction;
    out.frame_seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    if (on_frame) on_frame(k);
  }
}

RolloutResult standalone_rollout(LearnedSimulator& model, const Trajectory& t, int64_t first_frame,
                                 int64_t frames, double frame_dt,
                                 const std::function<void(int64_t)>& on_frame,
                                 const FrameCorrection& correct, double jitter, uint64_t seed) {
  RestartedRollout rollout = restart_rollout(t, first_frame, frames, frame_dt, jitter, seed);
  sph::Simulation& sim = *rollout.simulation;
  SceneRollout stepper(model, sim, t.material, frame_dt, t.source);
  const auto ids = active_ids(t, first_frame);
  stepper.set_history(ids, position_history(t, first_frame, ids, frame_dt) +
                               rollout.offset.index_select(0, ids).unsqueeze(1));
  record_frames(
      rollout, [&](int64_t k) { stepper.advance(int(first_frame + k), correct); }, on_frame);
  if (const sph::RiverFlow* flow = sim.flow())
    rollout.result.skipped_inflow_layers = flow->skipped_layers();
  return std::move(rollout.result);
}

}  // namespace gnn
