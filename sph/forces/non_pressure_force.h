#pragma once
// Interface of a non-pressure force. One force per file; make_non_pressure_forces() lists them.

#include <memory>
#include <string>
#include <vector>

#include "sph/boundary/boundary.h"
#include "sph/core/particle_set.h"
#include "sph/core/scene.h"
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

// The forces a scene asks for, in the order they are applied.
std::vector<std::unique_ptr<NonPressureForce>> make_non_pressure_forces(const SceneConfig& scene);

}  // namespace sph
