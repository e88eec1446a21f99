#include "sph/simulation/simulation.h"

#include "sph/river/leak.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "common/stopwatch.h"
#include "sph/core/config.h"
#include "sph/core/particle_loops.h"
#include "sph/core/simulation_error.h"

namespace sph {

namespace {
std::string format_vec(const Vec3& p) {
  std::ostringstream s;
  s << "(" << p[0] << ", " << p[1] << ", " << p[2] << ")";
  return s.str();
}
}  // namespace

void Simulation::fill_terrain_with_water(Real volume) {
  const Terrain& t = *scene_.terrain_grid;
  const Real spacing = scene_.particle_diameter(), r = scene_.particle_radius;
  const Real level = scene_.terrain->water_level;
  const MaterialsConfig& m = scene_.materials;
  const PhaseMix water =
      mix_phases(0, m.water.density, m.water.viscosity, m.oil.density, m.oil.viscosity);
  // Columns stacked from the ground up (water_column): a lattice anchored anywhere else leaves
  // gaps of up to a spacing over an uneven bed, and the water dropped half a spacing and sloshed
  // at the start.
  const int nx = int(std::floor((t.max_x() - t.origin_x) / spacing + Real(1e-4)));
  const int ny = int(std::floor((t.max_y() - t.origin_y) / spacing + Real(1e-4)));
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      const Real x = t.origin_x + r + Real(ix) * spacing, y = t.origin_y + r + Real(iy) * spacing;
      if (!t.is_water(x, y)) continue;
      for (Real z : water_column(t, x, y, r, level))
        fluid_.add(Vec3(x, y, z), scene_.terrain->fill_velocity, volume, water);
    }
}

Simulation::Simulation(const SceneConfig& scene)
    : scene_(scene), kernel_(kernel_kind(scene.kernel)) {
  boundary_ = build_boundary(scene_.boxes, boundary_height_fields(scene_),
                             scene_.particle_diameter(), scene_.support_radius(), kernel_);
  const Real volume = particle_rest_volume(scene_);
  add_initial_fluid(volume);
  // Leaks are emitters over the river (validated with the scene, so the file name is moot).
  std::vector<EmitterConfig> emitter_configs = scene_.emitters;
  for (size_t k = 0; k < scene_.leaks.size(); ++k)
    emitter_configs.push_back(leak_emitter(scene_.leaks[k], *scene_.terrain_grid,
                                           scene_.terrain->water_level, scene_.name, k));
  add_sources(emitter_configs, volume);
  domain_ = scene_.domain ? Aabb{scene_.domain->min, scene_.domain->max}
                          : geometry_domain(emitter_configs);
  try {
    neighbourhood_ = std::make_unique<ParticleNeighbourhood>(domain_, kernel_,
                                                             scene_.support_radius(), boundary_);
  } catch (const PointOutsideDomain& e) {
    // The boundary layer sits up to a support radius behind the declared surfaces.
    throw SimulationError("boundary particle " + std::to_string(e.index()) + " at " +
                          format_vec(e.point()) + " lies outside the domain [" +
                          format_vec(domain_.min) + ", " + format_vec(domain_.max) +
                          "]: grow /domain by a support radius (" +
                          std::to_string(scene_.support_radius()) + " m) around the geometry");
  }
  const PhysicsContext physics = scene_.physics();
  solver_ = make_pressure_solver(physics);
  forces_ = make_non_pressure_forces(physics, pressure_solver_entry(scene_.solver).forces);
  // Explicit viscosity is stable for dt <= 0.125 h^2 / nu (Morris, Fox & Zhu, J. Comput. Phys.
  // 136 (1997), eq. 36, with their smoothing length h = half our support radius = one particle
  // spacing). Oil at 4 x water's viscosity needs this: without it an oil layer at rest blew up.
  Real nu_max = scene_.boundary.friction;  // of the particles present, not of unused materials
  for (Real nu : fluid_.viscosity) nu_max = std::max(nu_max, nu);
  const Real spacing = scene_.particle_diameter();
  if (nu_max > 0) viscous_dt_limit_ = Real(0.125) * spacing * spacing / nu_max;
  check_initial_positions();
}

void Simulation::add_initial_fluid(Real volume) {
  const MaterialsConfig& m = scene_.materials;
  for (const auto& block : scene_.fluid_blocks) {
    const PhaseMix mix = mix_phases(block.oil_fraction(), m.water.density, m.water.viscosity,
                                    m.oil.density, m.oil.viscosity);
    for (const auto& p : lattice_points(block.min, block.max, scene_.particle_diameter()))
      fluid_.add(p, block.velocity, volume, mix);
  }
  if (scene_.terrain && scene_.terrain->fill_water) fill_terrain_with_water(volume);
}

void Simulation::add_sources(const std::vector<EmitterConfig>& emitter_configs, Real volume) {
  const Real spacing = scene_.particle_diameter();
  const MaterialsConfig& m = scene_.materials;
  for (size_t k = 0; k < emitter_configs.size(); ++k) {
    const EmitterConfig& e = emitter_configs[k];
    try {
      emitters_.emplace_back(e, spacing, volume,
                             mix_phases(e.material == "oil" ? 1 : 0, m.water.density,
                                        m.water.viscosity, m.oil.density, m.oil.viscosity));
    } catch (const std::invalid_argument& error) {
      throw SimulationError("emitter " + std::to_string(k) + ": " + error.what());
    }
    emitters_.back().allocate(fluid_);
  }
  if (!scene_.flow) return;
  try {
    flow_ = std::make_unique<RiverFlow>(
        *scene_.flow, *scene_.terrain_grid, scene_.terrain->water_level, spacing, volume,
        mix_phases(0, m.water.density, m.water.viscosity, m.oil.density, m.oil.viscosity),
        double(scene_.output.frame_dt));
  } catch (const std::invalid_argument& error) {
    throw SimulationError(std::string("flow: ") + error.what());
  }
  flow_->allocate(fluid_);
}

Aabb Simulation::geometry_domain(const std::vector<EmitterConfig>& emitter_configs) const {
  Aabb d{fluid_.size() ? fluid_.position[0] : Vec3::Zero(),
         fluid_.size() ? fluid_.position[0] : Vec3::Zero()};
  for (const auto& p : boundary_.position) {
    d.min = d.min.cwiseMin(p);
    d.max = d.max.cwiseMax(p);
  }
  for (const auto& b : scene_.fluid_blocks) {
    d.min = d.min.cwiseMin(b.min);
    d.max = d.max.cwiseMax(b.max);
  }
  for (const auto& e : emitter_configs) {
    d.min = d.min.cwiseMin(e.centre);
    d.max = d.max.cwiseMax(e.centre);
  }
  d.min.array() -= scene_.support_radius();
  d.max.array() += scene_.support_radius();
  return d;
}

void Simulation::check_initial_positions() const {
  for (Index i = 0; i < fluid_.active_count(); ++i)
    if (!domain_.contains(fluid_.position[i]))
      throw SimulationError("fluid particle " + std::to_string(i) + " at " +
                            format_vec(fluid_.position[i]) + " starts outside the domain");
  for (size_t k = 0; k < emitters_.size(); ++k)
    for (const Vec3& p : emitters_[k].layer())
      if (!domain_.contains(p))
        throw SimulationError("emitter " + std::to_string(k) + ": its outlet reaches " +
                              format_vec(p) + ", outside the domain [" + format_vec(domain_.min) +
                              ", " + format_vec(domain_.max) + "]");
}

void Simulation::update_neighbourhood() {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    neighbourhood_->update(fluid_, boundary_);
  } catch (const PointOutsideDomain& e) {
    const Index i = e.index();
    throw SimulationError(
        "frame " + std::to_string(current_frame_) + " (t = " + std::to_string(time_) +
        " s): particle " + std::to_string(fluid_.id[i]) + " left the domain [" +
        format_vec(domain_.min) + ", " + format_vec(domain_.max) + "] at " +
        format_vec(fluid_.position[i]) + " with velocity " + format_vec(fluid_.velocity[i]));
  }
  time_split_.neighbour_search += common::seconds_since(t0);
}

void Simulation::update_pair_kernels() {
  const auto t0 = std::chrono::steady_clock::now();
  neighbourhood_->update_pair_kernels(fluid_, boundary_);
  time_split_.neighbour_search += common::seconds_since(t0);
}

Real Simulation::choose_time_step(Real solver_limit) {
  const long n = long(fluid_.active_count());
  Real v2_max = 0;
#pragma omp parallel for schedule(static) reduction(max : v2_max)
  for (long i = 0; i < n; ++i) v2_max = std::max(v2_max, fluid_.velocity[size_t(i)].squaredNorm());
  const auto& ts = scene_.time_step;
  Real dt = ts.dt_max;
  if (v2_max > 0) dt = ts.cfl * Real(0.4) * scene_.particle_diameter() / std::sqrt(v2_max);
  dt = std::clamp(dt, ts.dt_min, ts.dt_max);
  dt = std::min({dt, solver_limit, viscous_dt_limit_});
  // End exactly on the frame: split the remaining time into equal steps no longer than dt.
  const double remaining = step_end_ - time_;
  const double parts = std::max(1.0, std::ceil(remaining / double(dt) - 1e-6));
  return Real(remaining / parts);
}

void Simulation::compute_non_pressure_accelerations(Real dt) {
  for_each_active(
      fluid_, [&](Index i) { fluid_.acceleration[i].setZero(); }, Schedule::kStatic);
  for (auto& force : forces_) {
    const auto t0 = std::chrono::steady_clock::now();
    force->add_acceleration(fluid_, boundary_, *neighbourhood_, dt);
    time_split_.forces[force->name()] += common::seconds_since(t0);
  }
}

void Simulation::check_state(int frame) const {
  const long n = long(fluid_.active_count());
  long bad = -1;
#pragma omp parallel for schedule(static) reduction(max : bad)
  for (long i = 0; i < n; ++i)
    if (!fluid_.position[size_t(i)].allFinite() || !fluid_.velocity[size_t(i)].allFinite())
      bad = std::max(bad, i);
  if (bad >= 0)
    throw SimulationError("frame " + std::to_string(frame) + " (t = " + std::to_string(time_) +
                          " s): particle " + std::to_string(fluid_.id[size_t(bad)]) +
                          " has a non-finite state: position " +
                          format_vec(fluid_.position[size_t(bad)]) + ", velocity " +
                          format_vec(fluid_.velocity[size_t(bad)]) +
                          " (the time step may be too large for the solver)");
}

void Simulation::reorder_by_cell() {
  // cell_order() is from the last neighbour search, before the last advection; it is still a
  // good locality order, and any permutation is correct.
  // Permuting the particles leaves the neighbourhood, and so `order`, untouched.
  const std::vector<Index>& order = neighbourhood_->cell_order();
  if (order.size() != fluid_.active_count()) return;
  fluid_.permute(order);
  solver_->permute(order);
}

FrameStats Simulation::advance_to(double t_end, int frame) {
  FrameStats stats;
  step_end_ = t_end;
  current_frame_ = frame;
  const double eps = 1e-9 * std::max(1.0, std::abs(t_end));
  double err_sum = 0, it_density = 0, it_divergence = 0;
  while (time_ < t_end - eps) {
    const auto t0 = std::chrono::steady_clock::now();
    for (auto& emitter : emitters_) emitter.emit(fluid_, time_);
    if (flow_) flow_->emit(fluid_, time_);
    StepStats step;
    solver_->step(*this, step);
    time_ += double(step.dt);
    if (flow_) flow_->after_step(fluid_, time_, step.dt);
    ++steps_;
    ++stats.steps;
    check_state(frame);
    if (scene_.reorder_interval > 0 && steps_ % scene_.reorder_interval == 0) reorder_by_cell();
    time_split_.total += common::seconds_since(t0);
    err_sum += step.density_error_avg;
    stats.density_error_max = std::max(stats.density_error_max, step.density_error_max);
    it_density += step.iterations_density;
    it_divergence += step.iterations_divergence;
    stats.dt_min = stats.steps == 1 ? double(step.dt) : std::min(stats.dt_min, double(step.dt));
    stats.dt_max = std::max(stats.dt_max, double(step.dt));
  }
  time_ = std::max(time_, t_end);
  if (stats.steps > 0) {
    stats.density_error_avg = err_sum / stats.steps;
    stats.iterations_density = it_density / stats.steps;
    stats.iterations_divergence = it_divergence / stats.steps;
  }
  return stats;
}

double Simulation::kinetic_energy() const {
  double e = 0;
  for (Index i = 0; i < fluid_.active_count(); ++i)
    e += 0.5 * double(fluid_.rest_density[i] * fluid_.rest_volume[i]) *
         double(fluid_.velocity[i].squaredNorm());
  return e;
}

}  // namespace sph
