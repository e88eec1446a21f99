#pragma once
// The physical settings of a scene that pressure solvers and non-pressure forces are built from:
// the ground floor's narrow view of a scene (sph/scene/scene.h builds it with physics_context()),
// so that solvers, forces and their registries know nothing of geometry, sources or outputs.

#include <string>

#include "common/config_section.h"
#include "sph/core/config.h"
#include "sph/core/kernels.h"
#include "sph/core/types.h"

namespace sph {

struct TimeStepConfig {
  Real cfl = 1;
  Real dt_min = Real(1e-5);
  Real dt_max = Real(0.005);
  template <class V>
  void describe(V& v) {
    v.field("cfl", cfl,
            param("", "CFL number lambda in dt = lambda * 0.4 * diameter / |v|max")
                .positive()
                .at_most(10));
    v.field("dt_min", dt_min, param("s", "Smallest time step").positive());
    v.field("dt_max", dt_max, param("s", "Largest time step").positive());
  }
  void check(const std::string& file, const std::string& pointer) const {
    if (dt_min > dt_max)
      throw ConfigError(
          file, pointer + "/dt_min",
          "expected <= dt_max (" + std::to_string(dt_max) + "), got " + std::to_string(dt_min));
  }
};

struct FluidMaterialConfig {
  Real density = 1000;
  Real viscosity = Real(0.01);
  template <class V>
  void describe(V& v) {
    v.field("density", density, param("kg/m^3", "Rest density").positive());
    v.field(
        "viscosity", viscosity,
        param("m^2/s", "Kinematic viscosity of the SPH Laplacian viscosity force").non_negative());
  }
};

// The two fluid phases. A particle carries their volume fractions; its rest density and
// viscosity are the fraction-weighted mixture (Ren et al. 2014).
struct MaterialsConfig {
  FluidMaterialConfig water{1000, Real(0.01)};
  // The reference crude oil: 0.94 x water's density, 4 x its viscosity.
  FluidMaterialConfig oil{940, Real(0.04)};
  template <class V>
  void describe(V& v) {
    v.field("water", water, param("", "Water"));
    v.field("oil", oil, param("", "Oil"));
  }
};

// What a registry entry (PressureSolverEntry::make, NonPressureForceEntry::make and ::wanted)
// may read of the scene.
struct PhysicsContext {
  std::string solver;  // the scene's pressure solver (its registry name)
  KernelKind kernel = KernelKind::kCubicSpline;
  Real particle_radius = Real(0.025);
  Real support_radius = Real(0.1);
  Vec3 gravity = Vec3(0, 0, Real(-9.81));
  TimeStepConfig time_step;
  MaterialsConfig materials;
  Real boundary_friction = 0;  // /boundary/friction
  Real xsph = 0;
  common::ConfigSections sections;  // every registered solver's and force's settings

  Real particle_diameter() const { return 2 * particle_radius; }
  // The settings section `key` of a solver or force, as the struct its owner declared.
  template <class T>
  const T& settings(const std::string& key) const {
    return sections.get<T>(key);
  }
};

}  // namespace sph
