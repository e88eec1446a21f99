#pragma once
// Interface of a non-pressure force. One force per file, which also declares its settings and its
// registry entry; the registry (force_registry.cpp) lists the entries.

#include <memory>
#include <string>
#include <vector>

#include "common/config_section.h"
#include "sph/boundary/boundary.h"
#include "sph/core/particle_set.h"
#include "sph/core/physics_context.h"
#include "sph/neighbours/neighbourhood.h"

namespace sph {

class NonPressureForce {
 public:
  virtual ~NonPressureForce() = default;
  virtual std::string name() const = 0;
  // Adds this force's acceleration to fluid.acceleration of every active particle. `dt` is the
  // step about to be taken (velocity filters such as XSPH express their change as dv/dt).
  virtual void add_acceleration(FluidParticles& fluid, const BoundaryParticles& boundary,
                                const ParticleNeighbourhood& neighbourhood, Real dt) = 0;
};

// How a force is registered (one line in force_registry.cpp).
struct NonPressureForceEntry {
  std::string name;
  // Its settings, declared beside its code, each under its scene key.
  std::vector<common::ConfigSectionEntry> sections;
  // Whether the scene asks for it by itself (gravity always, viscosity when a phase is viscous);
  // a pressure solver can also ask for it by name (PressureSolverEntry::forces).
  bool (*wanted)(const PhysicsContext& physics);
  std::unique_ptr<NonPressureForce> (*make)(const PhysicsContext& physics);
};

// Every registered force, in the order forces are applied.
std::vector<NonPressureForceEntry> non_pressure_force_entries();

// The forces the scene asks for (NonPressureForceEntry::wanted) and those its pressure solver
// asks for by name (`asked_by_solver`: PressureSolverEntry::forces), in the order they are applied.
std::vector<std::unique_ptr<NonPressureForce>> make_non_pressure_forces(
    const PhysicsContext& physics, const std::vector<std::string>& asked_by_solver);

}  // namespace sph
