#pragma once
// Interface of a pressure solver. One solver per file pair, which also declares its settings and
// its registry entry; the registry (solver_registry.cpp) lists the entries.

#include <memory>
#include <string>
#include <vector>

#include "common/config_section.h"
#include "sph/core/physics_context.h"
#include "sph/solvers/solver_host.h"

namespace sph {

class PressureSolver {
 public:
  virtual ~PressureSolver() = default;
  virtual std::string name() const = 0;
  // Advances the host by one time step.
  virtual void step(SolverHost& host, StepStats& stats) = 0;
  // Reorders per-particle solver state (e.g. warm-start pressures) like FluidParticles::permute.
  virtual void permute(const std::vector<Index>& order) = 0;
};

// How a solver is registered (one line in solver_registry.cpp): everything about it that the rest
// of the simulator needs, so nothing else tests a solver's name.
struct PressureSolverEntry {
  std::string name;  // the scene's `solver` value
  // Its settings, declared beside its code, each under its scene key.
  std::vector<common::ConfigSectionEntry> sections;
  // Non-pressure forces it adds to those the scene asks for (NonPressureForceEntry::name).
  std::vector<std::string> forces;
  std::unique_ptr<PressureSolver> (*make)(const PhysicsContext& physics);
};

// Every registered solver, in the registry's order, and their names.
std::vector<PressureSolverEntry> pressure_solver_entries();
std::vector<std::string> pressure_solver_names();
// The entry of `name`. Throws std::invalid_argument for an unknown name.
PressureSolverEntry pressure_solver_entry(const std::string& name);

// Builds the solver named in physics.solver. Throws std::invalid_argument for an unknown name.
std::unique_ptr<PressureSolver> make_pressure_solver(const PhysicsContext& physics);

}  // namespace sph
