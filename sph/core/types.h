#pragma once
// Scalar and vector types shared by the whole simulator.

#include <Eigen/Core>
#include <cstdint>

namespace sph {

#ifdef SPILL_DOUBLE
using Real = double;
#else
using Real = float;
#endif

using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Vec3d = Eigen::Matrix<double, 3, 1>;
// Particle indices: 32 bits are enough for the scenes we run (tens of millions at most) and halve
// the memory traffic of the neighbour lists compared with 64-bit indices.
using Index = std::uint32_t;

// Particle type codes of the data contract (docs/design.md): 0 water, 1 oil, 2 boundary.
enum class ParticleType : std::int32_t { kWater = 0, kOil = 1, kBoundary = 2 };

// Axis-aligned box.
struct Aabb {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
  bool contains(const Vec3& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
};

}  // namespace sph
