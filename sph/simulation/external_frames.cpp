// Frames computed outside the solver: the scene's sources and sinks around a caller's prediction
// (a learned simulator's), and the state of a recorded frame to start from.

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "sph/simulation/simulation.h"

namespace sph {

void Simulation::release_sources() {
  for (auto& emitter : emitters_) emitter.emit(fluid_, time_);
  if (flow_) flow_->emit(fluid_, time_, /*skip_when_empty=*/true);
}

ExternalFrameStats Simulation::apply_external_frame(double t_end, const std::vector<Vec3>& position,
                                                    const std::vector<Real>& oil_fraction,
                                                    int frame) {
  const Index n = fluid_.active_count();
  if (position.size() != n || oil_fraction.size() != n)
    throw std::invalid_argument("apply_external_frame: " + std::to_string(position.size()) +
                                " positions and " + std::to_string(oil_fraction.size()) +
                                " oil fractions for " + std::to_string(n) + " active particles");
  const double dt = t_end - time_;
  if (!(dt > 0))
    throw std::invalid_argument("apply_external_frame: t_end " + std::to_string(t_end) +
                                " s is not after the simulation's time " + std::to_string(time_));
  const MaterialsConfig& m = scene_.materials;
  // By slot: nothing moves between slots until the retirement.
  std::vector<Vec3> previous(n);
  for (Index i = 0; i < n; ++i) {
    if (!position[i].allFinite())
      throw SimulationError("frame " + std::to_string(frame) + " (t = " + std::to_string(t_end) +
                            " s): particle " + std::to_string(fluid_.id[i]) +
                            " was given a non-finite position");
    previous[i] = fluid_.position[i];
    fluid_.velocity[i] = (position[i] - fluid_.position[i]) / Real(dt);
    fluid_.position[i] = position[i];
    fluid_.set_mix(i, mix_phases(std::clamp(oil_fraction[i], Real(0), Real(1)), m.water.density,
                                 m.water.viscosity, m.oil.density, m.oil.viscosity));
  }
  time_ = t_end;
  ExternalFrameStats stats;
  if (flow_) {
    // A velocity the flow holds moves its particle, as the solver's steps would have; then what
    // has left the reach retires.
    flow_->hold_buffers_over_frame(fluid_, previous, Real(dt));
    const long before = long(fluid_.active_count());
    flow_->retire_leaving(fluid_, time_);
    stats.retired = before - long(fluid_.active_count());
  }
  // Outside the domain a particle has left the reach too: in a river it retires as at the
  // outflow (water back to the inflow's pool, its oil counted as gone), so a forecast that loses
  // particles through the bed or the lid keeps its water.
  for (Index i = fluid_.active_count(); i-- > 0;)
    if (!domain_.contains(fluid_.position[i])) {
      if (flow_)
        flow_->retire(fluid_, i, time_);
      else
        fluid_.deactivate(i);
      ++stats.left_domain;
    }
  return stats;
}

void Simulation::restore_recorded_frame(const RecordedFrame& frame, double frame_dt) {
  const Index n = fluid_.size();
  if (frame.position.size() != n || frame.velocity.size() != n || frame.oil_fraction.size() != n ||
      frame.active.size() != n)
    throw std::invalid_argument("the recorded frame has " + std::to_string(frame.position.size()) +
                                " particles, the scene " + std::to_string(n));
  // Slots in identity order, the active ones first.
  std::vector<Index> slot_of(n), order;
  for (Index i = 0; i < n; ++i) slot_of[fluid_.id[i]] = i;
  for (int pass = 0; pass < 2; ++pass)
    for (Index id = 0; id < n; ++id)
      if (bool(frame.active[id]) == (pass == 0)) order.push_back(slot_of[id]);
  fluid_.for_each_array([&](const char*, auto& values, bool) {
    std::remove_reference_t<decltype(values)> scratch;
    permute_array(values, order, scratch);
  });
  const MaterialsConfig& m = scene_.materials;
  fluid_.active = 0;
  for (Index i = 0; i < n; ++i) {
    const Index id = fluid_.id[i];
    fluid_.active += frame.active[id] ? 1 : 0;
    fluid_.position[i] = frame.position[id];
    fluid_.velocity[i] = frame.velocity[id];
    fluid_.acceleration[i].setZero();
    fluid_.density[i] = 1;
    fluid_.pressure[i] = 0;
    fluid_.set_mix(i, mix_phases(frame.oil_fraction[id], m.water.density, m.water.viscosity,
                                 m.oil.density, m.oil.viscosity));
  }
  time_ = frame.time;
  // An emitter has released every layer due a frame ago (its steps began by then) and every
  // layer with a particle active now; a layer due within the last frame may or may not be out.
  std::vector<Index> emitted(emitters_.size());
  for (size_t k = 0; k < emitters_.size(); ++k) {
    long layers = long(emitters_[k].layers_due(frame.time - frame_dt));
    for (Index id = 0; id < n; ++id)
      if (frame.active[id]) layers = std::max(layers, emitters_[k].layer_of(id) + 1);
    emitters_[k].restore(Index(layers));
    emitted[k] = Index(layers);
  }
  if (!flow_) return;
  // The inflow's newest water is the most upstream particle held in its buffer; the pool is the
  // inactive water (by the oil rule: a retired trace of oil returns) that no emitter still holds
  // back.
  Real newest_x = std::numeric_limits<Real>::quiet_NaN();
  for (Index id = 0; id < n; ++id)
    if (frame.active[id] && frame.position[id].x() < flow_->buffer_end() &&
        !(newest_x <= frame.position[id].x()))
      newest_x = frame.position[id].x();
  std::vector<Index> pool;
  for (Index id = 0; id < n; ++id) {
    if (frame.active[id] || is_oil(frame.oil_fraction[id])) continue;
    bool held_back = false;
    for (size_t k = 0; k < emitters_.size(); ++k) {
      const long layer = emitters_[k].layer_of(id);
      held_back = held_back || (layer >= 0 && layer >= long(emitted[k]));
    }
    if (!held_back) pool.push_back(id);
  }
  flow_->restore_recorded(frame.time, newest_x, pool);
}

}  // namespace sph
