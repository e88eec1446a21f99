#pragma once
// What a pressure solver may ask of the simulation that runs it. A solver owns the order of one
// time step (DFSPH solves before and after advection, WCSPH only before), the host owns the
// particles, neighbourhood, forces and time-step policy.

#include <map>
#include <string>

#include "sph/boundary/boundary.h"
#include "sph/core/particle_set.h"
#include "sph/neighbours/neighbourhood.h"

namespace sph {

// Wall-clock seconds spent in each part of the simulation.
struct TimeSplit {
  double neighbour_search = 0;  // grid, neighbour lists, pair kernels, densities
  double pressure_solve = 0;    // the pressure solver's own work
  // Parts of a solver's own step that it times by name (MTDF-SPH: "mixture_model", its drift,
  // drift momentum and fraction transport); reported beside the parts above.
  std::map<std::string, double> solver_parts;
  std::map<std::string, double> forces;  // each non-pressure force, by name
  double total = 0;                      // everything in step()
  // What no part above accounts for (time step choice, integration, emitters, checks).
  double other() const {
    double rest = total - neighbour_search - pressure_solve;
    for (const auto& [name, seconds] : solver_parts) rest -= seconds;
    for (const auto& [name, seconds] : forces) rest -= seconds;
    return rest;
  }
};

// Figures of one solver step.
struct StepStats {
  Real dt = 0;
  int iterations_density = 0;
  int iterations_divergence = 0;
  double density_error_avg = 0;  // mean of max(rho/rho0 - 1, 0) after the solve
  double density_error_max = 0;  // largest rho/rho0 - 1 after the solve
};

class SolverHost {
 public:
  virtual ~SolverHost() = default;
  virtual FluidParticles& mutable_fluid() = 0;
  virtual const BoundaryParticles& boundary() const = 0;
  virtual const ParticleNeighbourhood& neighbourhood() const = 0;
  // Neighbour search, pair kernels and densities for the current positions.
  virtual void update_neighbourhood() = 0;
  // Pair kernels and densities for the current positions on the last search's pairs
  // (ParticleNeighbourhood::update_pair_kernels).
  virtual void update_pair_kernels() = 0;
  // Chooses dt (CFL, clamped to the scene's range and `solver_limit`, ending on the next frame).
  virtual Real choose_time_step(Real solver_limit) = 0;
  // Overwrites fluid().acceleration with the non-pressure accelerations (gravity, viscosity, ...).
  virtual void compute_non_pressure_accelerations(Real dt) = 0;
  virtual TimeSplit& time_split() = 0;
};

}  // namespace sph
