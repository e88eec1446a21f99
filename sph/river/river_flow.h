#pragma once
// Inflow and outflow of a river reach. Water enters through the channel's cross-section at
// inflow_x: every spacing / speed seconds a layer of particles (the lattice of the cross-section
// between the ground and the water level) is activated there moving at `speed` along +x, and over
// the `buffer` downstream of the plane every particle is held at that velocity, so the inflow
// keeps a steady profile and the reach cannot push water back through it. Particles past
// outflow_x are retired (active = 0); over the `buffer` upstream of that plane their velocity
// along x is held at `speed` too, so the reach drains as fast as it fills. Particles that fall
// two spacings below the lowest ground (over a bank and off an edge of the terrain) have left
// the reach as well and are retired the same way. Retired water particles (by the one oil rule,
// is_oil: a trace of oil the mixture gave a water particle does not keep it out) return to the
// inflow's pool after two frames (so a recorded trajectory never shows a particle jump from the
// outflow to the inflow between two frames in which it is active) and re-enter as pure water; the
// oil they carried has left the reach and is counted so (oil_left_volume), so the oil budget
// closes. Oil stays retired, so a particle never changes phase. The pool starts with `reserve_s`
// seconds of inflow.

#include <deque>
#include <nlohmann/json.hpp>
#include <vector>

#include "sph/core/particle_set.h"
#include "sph/core/simulation_error.h"
#include "sph/river/river_configs.h"
#include "sph/river/terrain.h"

namespace sph {

class RiverFlow {
 public:
  // Throws std::invalid_argument when the inflow plane has no water cells below the level.
  RiverFlow(const FlowConfig& config, const Terrain& terrain, Real water_level, Real spacing,
            Real volume, const PhaseMix& water, double frame_dt);

  // Appends the pool's particles, inactive, to `fluid` (once, before the run).
  void allocate(FluidParticles& fluid);
  // Activates the inflow layers due by time t. Throws SimulationError when the pool is empty,
  // unless `skip_when_empty`: then a layer the pool cannot fill is skipped and counted (a
  // learned forecast whose reach backs up, so that the outflow returns too little water, goes
  // on with less inflow and says so; a solver run stops).
  void emit(FluidParticles& fluid, double t, bool skip_when_empty = false);
  long skipped_layers() const { return skipped_layers_; }
  // After a step of dt ending at time t: with `plug`, moves the inflow buffer's water along x by
  // the inflow speed over the step; holds the buffers' velocity and retires the particles past
  // the outflow plane.
  void after_step(FluidParticles& fluid, double t, Real dt);
  // The two halves of after_step: the buffers' held velocity, then the retirement.
  void hold_buffers(FluidParticles& fluid) const;
  void retire_leaving(FluidParticles& fluid, double t);
  // For a frame computed outside the solver, which moved every particle from `previous` to its
  // position over dt: the buffers' hold applied as a solver's steps would have applied it. Water
  // in the inflow buffer at the frame's end moved at the inflow velocity all frame; water in the
  // outflow buffer moved along x at the inflow speed for the part of the frame it spent there,
  // and at its predicted pace before it reached the buffer (held for the whole frame instead, the
  // water that entered the buffer during the frame fell behind the solver's, which speeds up
  // towards the outflow, and a learned reach kept about a layer more than the recording).
  void hold_buffers_over_frame(FluidParticles& fluid, const std::vector<Vec3>& previous,
                               Real dt) const;
  // Retires the active particle at `slot`, which has left the reach at time t (retire_leaving's
  // rule for one particle; a forecast's particle outside the domain): water returns to the pool,
  // the oil it carries counts as gone. Not counted in retired().
  void retire(FluidParticles& fluid, Index slot, double t);

  const std::vector<Vec3>& layer() const { return layer_; }
  // The inflow plane's cross-section of water below `water_level`, a particle per lattice site.
  // Throws std::invalid_argument when the plane crosses no water (the scene check calls it).
  static std::vector<Vec3> inflow_layer(const FlowConfig& config, const Terrain& terrain,
                                        Real water_level, Real spacing);
  long fallen() const { return fallen_; }    // of the retired: those that left over a terrain edge
  long emitted() const { return emitted_; }  // particles activated at the inflow so far
  long retired() const { return retired_; }  // particles retired at the outflow so far
  // Oil volume (m^3, fraction x rest volume) that has left the reach in retired particles, water
  // with a trace of oil included: with the oil on the water it makes up the oil released.
  double oil_left_volume() const { return oil_left_volume_; }
  Real inflow_rate() const;  // m^3/s
  // Progress and reserve, for saved simulation states.
  nlohmann::json state() const;
  void restore(const nlohmann::json& state);
  // Continues from a recorded frame at time t (the counts start from zero): the layers released
  // so far follow from `newest_x`, where the most upstream water of the inflow buffer is (it
  // moves at the inflow speed from its due time; NaN when none is there), and the pool is
  // `pool`, free at once.
  void restore_recorded(double t, Real newest_x, const std::vector<Index>& pool);
  Real inflow_x() const { return config_.inflow_x; }
  Real buffer_end() const { return config_.inflow_x + config_.buffer; }
  Real outflow_buffer_start() const { return config_.outflow_x - config_.buffer; }

 private:
  struct PoolEntry {
    Index id;
    double free_from;  // time from which the particle may re-enter
  };
  FlowConfig config_;
  Real volume_;
  PhaseMix water_;
  double cooldown_;
  std::vector<Vec3> layer_;
  double interval_ = 0;
  long emitted_layers_ = 0;
  long emitted_ = 0, retired_ = 0, fallen_ = 0;
  long skipped_layers_ = 0;
  double oil_left_volume_ = 0;
  Real floor_z_;  // below this a particle has left the reach over an edge of the terrain
  // Beyond the terrain's sides (across the flow, and upstream of its start) there is no ground:
  // a particle there has been thrown over the edge and has left the reach too.
  Real ground_min_x_, ground_min_y_, ground_max_y_;
  std::deque<PoolEntry> pool_;
  std::vector<Index> retiring_;
};

}  // namespace sph
