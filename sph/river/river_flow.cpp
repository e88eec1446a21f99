#include "sph/river/river_flow.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "sph/core/config.h"
#include "sph/core/simulation_error.h"

namespace sph {

RiverFlow::RiverFlow(const FlowConfig& config, const Terrain& terrain, Real water_level,
                     Real spacing, Real volume, const PhaseMix& water, double frame_dt)
    : config_(config),
      volume_(volume),
      water_(water),
      cooldown_(2 * frame_dt),
      layer_(inflow_layer(config, terrain, water_level, spacing)),
      floor_z_(terrain.min_height() - 2 * spacing),
      ground_min_x_(terrain.origin_x - Real(0.5) * terrain.cell_size),
      ground_min_y_(terrain.origin_y - Real(0.5) * terrain.cell_size),
      ground_max_y_(terrain.max_y() + Real(0.5) * terrain.cell_size) {
  interval_ = double(spacing) / double(config.speed);
  const long reserve_layers = std::max(2L, std::lround(double(config.reserve_s) / interval_));
  pool_.resize(size_t(reserve_layers) * layer_.size());
}

std::vector<Vec3> RiverFlow::inflow_layer(const FlowConfig& config, const Terrain& terrain,
                                          Real water_level, Real spacing) {
  // The cross-section on the lattice the terrain fill uses: water columns spacing apart in y.
  std::vector<Vec3> layer;
  const Real r = Real(0.5) * spacing, x = config.inflow_x;
  const int ny = int(std::floor((terrain.max_y() - terrain.origin_y) / spacing + Real(1e-4)));
  for (int iy = 0; iy < ny; ++iy) {
    const Real y = terrain.origin_y + r + Real(iy) * spacing;
    if (!terrain.is_water(x, y)) continue;
    for (Real z : water_column(terrain, x, y, r, water_level)) layer.emplace_back(x, y, z);
  }
  if (layer.empty())
    throw std::invalid_argument("the inflow plane x = " + std::to_string(x) +
                                " crosses no water below the water level");
  return layer;
}

Real RiverFlow::inflow_rate() const {
  return Real(double(volume_) * double(layer_.size()) / interval_);
}

nlohmann::json RiverFlow::state() const {
  std::vector<Index> ids;
  std::vector<double> free_from;
  for (const auto& e : pool_) {
    ids.push_back(e.id);
    // JSON has no infinity: the initial reserve is free from the start.
    free_from.push_back(std::isfinite(e.free_from) ? e.free_from : -1e300);
  }
  return {{"emitted_layers", emitted_layers_},
          {"emitted", emitted_},
          {"retired", retired_},
          {"fallen", fallen_},
          {"oil_left_volume", oil_left_volume_},
          {"pool_ids", ids},
          {"pool_free_from", free_from}};
}

void RiverFlow::restore(const nlohmann::json& s) {
  emitted_layers_ = s.at("emitted_layers");
  emitted_ = s.at("emitted");
  retired_ = s.at("retired");
  fallen_ = s.at("fallen");
  // States saved before the oil that left was counted start its count at zero.
  oil_left_volume_ = s.value("oil_left_volume", 0.0);
  const auto ids = s.at("pool_ids").get<std::vector<Index>>();
  const auto free_from = s.at("pool_free_from").get<std::vector<double>>();
  pool_.clear();
  for (size_t k = 0; k < ids.size(); ++k) pool_.push_back({ids[k], free_from.at(k)});
}

void RiverFlow::restore_recorded(double t, Real newest_x, const std::vector<Index>& pool) {
  // Layer k is due at (k + 1) interval and then travels at the inflow speed, so the newest layer
  // released by t sits at inflow_x + (t - due) speed: due, and the count, follow. Without water
  // in the buffer, every layer due by t is counted.
  double due = t;
  if (std::isfinite(double(newest_x)))
    due = t - double(newest_x - config_.inflow_x) / double(config_.speed);
  emitted_layers_ = std::max(0L, std::lround(due / interval_));
  emitted_ = retired_ = fallen_ = 0;
  oil_left_volume_ = 0;
  pool_.clear();
  for (Index id : pool) pool_.push_back({id, -std::numeric_limits<double>::infinity()});
}

void RiverFlow::allocate(FluidParticles& fluid) {
  const Vec3 velocity(config_.speed, 0, 0);
  for (size_t k = 0; k < pool_.size(); ++k) {
    pool_[k] = {fluid.size(), -std::numeric_limits<double>::infinity()};
    fluid.add(layer_[k % layer_.size()], velocity, volume_, water_, /*active=*/false);
  }
}

void RiverFlow::emit(FluidParticles& fluid, double t, bool skip_when_empty) {
  const Vec3 velocity(config_.speed, 0, 0);
  while (true) {
    // Layer k enters when layer k - 1 (or the initial fill, whose first column sits on the
    // plane) has moved one spacing on.
    const double due = double(emitted_layers_ + 1) * interval_;
    if (due > t) break;
    const Real travelled = Real(t - due) * config_.speed;
    const bool enough = pool_.size() >= layer_.size() && pool_[layer_.size() - 1].free_from <= t;
    if (!enough && skip_when_empty) {
      ++skipped_layers_;
      ++emitted_layers_;
      continue;
    }
    for (const Vec3& p : layer_) {
      if (pool_.empty() || pool_.front().free_from > t)
        throw SimulationError(
            "t = " + std::to_string(t) +
            " s: the inflow ran out of particles (the outflow returns fewer than enter); raise "
            "flow/reserve_s (now " +
            std::to_string(config_.reserve_s) + " s)");
      const Index slot = fluid.find_inactive(pool_.front().id);
      pool_.pop_front();
      fluid.activate(slot, p + Vec3(travelled, 0, 0), velocity);
      // Returned water may have carried a trace of oil out; it enters as the river's water.
      fluid.set_mix(fluid.active_count() - 1, water_);
      ++emitted_;
    }
    ++emitted_layers_;
  }
}

void RiverFlow::after_step(FluidParticles& fluid, double t, Real dt) {
  // With `plug`, the buffer's water moves along x by the inflow speed over the step, not by the
  // solver's velocity, which the held velocity only replaces after the step. Friction at the bed
  // slows the lowest particles within each step; where a layer takes long to fill its spacing
  // (0.39 s at 25 cm spacing and 0.64 m/s) they fell half a spacing behind by the time the next
  // layer entered, and the overlap blew a deep, slow river apart. Only x: across and up, the
  // solver keeps the water off a bed and banks that rise along the buffer.
  if (config_.plug) {
    const Real inflow_end = buffer_end();
    for (Index i = 0; i < fluid.active_count(); ++i)
      if (fluid.position[i].x() < inflow_end)
        fluid.position[i].x() += (config_.speed - fluid.velocity[i].x()) * dt;
  }
  hold_buffers(fluid);
  retire_leaving(fluid, t);
}

void RiverFlow::hold_buffers(FluidParticles& fluid) const {
  const Vec3 velocity(config_.speed, 0, 0);
  const Real inflow_end = buffer_end(), outflow_start = outflow_buffer_start();
  for (Index i = 0; i < fluid.active_count(); ++i) {
    const Real x = fluid.position[i].x();
    if (x < inflow_end) fluid.velocity[i] = velocity;
    // Held at the inflow speed downstream too, so the reach drains as fast as it fills: left
    // free, the water accelerates into the gap the retirement leaves and the level drops for
    // several depths upstream of the outflow.
    if (x > outflow_start) fluid.velocity[i].x() = config_.speed;
  }
}

void RiverFlow::hold_buffers_over_frame(FluidParticles& fluid, const std::vector<Vec3>& previous,
                                        Real dt) const {
  const Vec3 velocity(config_.speed, 0, 0);
  const Real inflow_end = buffer_end(), outflow_start = outflow_buffer_start();
  for (Index i = 0; i < fluid.active_count(); ++i) {
    const Vec3& from = previous[i];
    Vec3& x = fluid.position[i];
    if (x.x() < inflow_end) {
      fluid.velocity[i] = velocity;
      x = from + velocity * dt;
    } else if (x.x() > outflow_start) {
      // The share of the frame spent before the buffer, at the predicted pace along x.
      const Real before =
          from.x() < outflow_start ? (outflow_start - from.x()) / (x.x() - from.x()) : Real(0);
      x.x() = std::max(from.x(), outflow_start) + (1 - before) * config_.speed * dt;
      fluid.velocity[i].x() = config_.speed;
    }
  }
}

void RiverFlow::retire_leaving(FluidParticles& fluid, double t) {
  retiring_.clear();
  for (Index i = 0; i < fluid.active_count(); ++i) {
    // Past the outflow, or fallen below the lowest ground or thrown beyond its sides: water
    // that splashed over a bank and off the edge of the terrain has left the reach too (the
    // domain ends a little beyond the ground, and a particle there would end the run).
    const Vec3& p = fluid.position[i];
    const bool fell =
        p.z() < floor_z_ || p.y() < ground_min_y_ || p.y() > ground_max_y_ || p.x() < ground_min_x_;
    fallen_ += fell;
    if (p.x() > config_.outflow_x || fell) retiring_.push_back(i);
  }
  // From the highest slot down: deactivate() moves the last active particle into the freed slot,
  // and that one has been looked at already.
  for (auto it = retiring_.rbegin(); it != retiring_.rend(); ++it) {
    retire(fluid, *it, t);
    ++retired_;
  }
}

void RiverFlow::retire(FluidParticles& fluid, Index slot, double t) {
  const Index id = fluid.id[slot];
  const Real fraction = fluid.oil_fraction[slot];
  oil_left_volume_ += double(fraction) * double(fluid.rest_volume[slot]);
  fluid.deactivate(slot);
  if (!is_oil(fraction)) pool_.push_back({id, t + cooldown_});
}

}  // namespace sph
