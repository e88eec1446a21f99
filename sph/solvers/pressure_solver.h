#pragma once
// Interface of a pressure solver. One solver per file; the registry (solver_registry.cpp) maps
// the scene's lowercase `solver` name to a factory.

#include <memory>
#include <string>
#include <vector>

#include "sph/core/scene.h"
#include "sph/core/solver_host.h"

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

// Builds the solver named in scene.solver. Throws std::invalid_argument for an unknown name.
std::unique_ptr<PressureSolver> make_pressure_solver(const SceneConfig& scene);

}  // namespace sph
