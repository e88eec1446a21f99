#pragma once
// A Simulation owns one scene's state: fluid and boundary particles, neighbourhood, pressure
// solver, non-pressure forces, clock and time-step policy. Nothing global: two simulations can
// run side by side.

#include <limits>
#include <memory>
#include <vector>

#include "sph/boundary/boundary.h"
#include "sph/boundary/emitter.h"
#include "sph/core/lattice.h"
#include "sph/core/particle_set.h"
#include "sph/core/simulation_error.h"
#include "sph/forces/non_pressure_force.h"
#include "sph/neighbours/neighbourhood.h"
#include "sph/river/river_flow.h"
#include "sph/scene/scene.h"
#include "sph/solvers/pressure_solver.h"
#include "sph/solvers/solver_host.h"

namespace sph {

// A frame of a recording (a dataset's trajectory, by particle identity: index = id), to continue
// from with frames computed outside the solver (Simulation::restore_recorded_frame).
struct RecordedFrame {
  double time = 0;
  std::vector<Vec3> position, velocity;
  std::vector<Real> oil_fraction;
  std::vector<std::uint8_t> active;
};

// What one frame computed outside the solver retired (Simulation::apply_external_frame).
struct ExternalFrameStats {
  long retired = 0;      // past the outflow or fallen off the terrain (the river's own rules)
  long left_domain = 0;  // outside the domain: a solver run stops there, a forecast retires them
};

// Figures of the steps between two recorded frames.
struct FrameStats {
  int steps = 0;
  double density_error_avg = 0;      // mean over the steps
  double density_error_max = 0;      // max over the steps
  double iterations_density = 0;     // mean per step
  double iterations_divergence = 0;  // mean per step
  double dt_min = 0, dt_max = 0;
};

class Simulation : private SolverHost {
 public:
  explicit Simulation(const SceneConfig& scene);

  // Steps until time() reaches t_end (the last step is shortened to end exactly there).
  // `frame` is used in error messages. Throws SimulationError on NaN or a particle leaving the
  // domain.
  FrameStats advance_to(double t_end, int frame);

  double time() const { return time_; }
  long steps() const { return steps_; }
  const SceneConfig& scene() const { return scene_; }
  const FluidParticles& fluid() const { return fluid_; }
  const BoundaryParticles& boundary() const { return boundary_; }
  const Aabb& domain() const { return domain_; }
  const TimeSplit& timing() const { return time_split_; }
  const std::vector<Emitter>& emitters() const { return emitters_; }
  const RiverFlow* flow() const { return flow_.get(); }  // nullptr without a `flow`
  double kinetic_energy() const;                         // J, of the active fluid

  // The state of the run (every fluid particle, time, emitters' and river flow's progress) in an
  // HDF5 file, to continue from later, e.g. a river after its warm-up (simulation_state.cpp).
  // Solver warm starts are not saved: a continued run converges from a cold start, so it follows
  // the uninterrupted one closely but not bit for bit. load_state() throws ConfigError naming the
  // file and the key when the state does not fit this scene.
  void save_state(const std::string& file) const;
  void load_state(const std::string& file);

  // Frames computed outside the solver (a learned simulator: spill-infer predict, and eval
  // without the recording's help), with the scene's own sources and sinks acting once per frame
  // as they act once per step in a solver run (external_frames.cpp). A frame is:
  // release_sources(), then the caller's prediction for the active particles in fluid()'s
  // order, then apply_external_frame(), then release_sources() again (what became due during the
  // frame appears at its frame's end, advected from its due time, as in a solver run).
  //
  // Activates what the emitters and the river's inflow release by time(), each particle placed
  // where it would be now had it left at its due time (as in a solver run). An inflow layer its
  // pool cannot fill is skipped and counted (RiverFlow::skipped_layers), not an error.
  void release_sources();
  // Moves the active particles (in fluid()'s order, unchanged since release_sources()) to
  // `position` with oil fractions `oil_fraction` at time t_end, velocities from the displacement.
  // The river's buffers then hold their speed (the position follows the held velocity), and
  // particles past the outflow, fallen off the terrain or outside the domain retire. Throws
  // SimulationError naming `frame` when a position is not finite, std::invalid_argument when the
  // sizes differ from the active count.
  ExternalFrameStats apply_external_frame(double t_end, const std::vector<Vec3>& position,
                                          const std::vector<Real>& oil_fraction, int frame);
  // Continues from a recorded frame of this scene: every particle's state and activity, the
  // clock, and the sources' progress (an emitter has released every layer due a frame before the
  // recorded time and every layer holding an active particle; the inflow's last layer is found
  // from where its water is, the pool holds the inactive water, by the oil rule). Throws
  // std::invalid_argument when the frame's particle count differs from this scene's.
  void restore_recorded_frame(const RecordedFrame& frame, double frame_dt);

  // A per-particle array of fluid() in identity order (index = particle id), for writers:
  // e.g. in_id_order(fluid().position).
  template <class T>
  std::vector<T> in_id_order(const std::vector<T>& per_particle) const {
    std::vector<T> out(fluid_.size());
    for (Index i = 0; i < fluid_.size(); ++i) out[fluid_.id[i]] = per_particle[i];
    return out;
  }

 private:
  // SolverHost
  FluidParticles& mutable_fluid() override { return fluid_; }
  const ParticleNeighbourhood& neighbourhood() const override { return *neighbourhood_; }
  void update_neighbourhood() override;
  void update_pair_kernels() override;
  Real choose_time_step(Real solver_limit) override;
  void compute_non_pressure_accelerations(Real dt) override;
  TimeSplit& time_split() override { return time_split_; }

  void check_state(int frame) const;
  // The fluid blocks and the terrain's water fill, each particle of rest volume `volume`.
  void add_initial_fluid(Real volume);
  // Water at rest in the terrain's water cells, from the ground up to terrain.water_level.
  void fill_terrain_with_water(Real volume);
  // The emitters (the scene's and its leaks') and the river's inflow, with their reserves.
  void add_sources(const std::vector<EmitterConfig>& emitter_configs, Real volume);
  // Without a /domain: the box around boundary, fluid and emitters, grown by a support radius.
  Aabb geometry_domain(const std::vector<EmitterConfig>& emitter_configs) const;
  // Every fluid particle and emitter outlet must start inside the domain.
  void check_initial_positions() const;
  void reorder_by_cell();

  SceneConfig scene_;
  KernelKind kernel_;
  BoundaryParticles boundary_;
  FluidParticles fluid_;
  Aabb domain_;
  std::unique_ptr<ParticleNeighbourhood> neighbourhood_;
  std::unique_ptr<PressureSolver> solver_;
  std::vector<std::unique_ptr<NonPressureForce>> forces_;
  std::vector<Emitter> emitters_;
  std::unique_ptr<RiverFlow> flow_;
  TimeSplit time_split_;
  Real viscous_dt_limit_ = std::numeric_limits<Real>::infinity();
  double time_ = 0;
  double step_end_ = 0;  // time the current advance_to() must end on
  long steps_ = 0;
  int current_frame_ = 0;
};

}  // namespace sph
