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

// The one oil rule. A fluid particle's phase in a frame is its oil volume fraction, not the type
// it was made with (MTDF-SPH's mixture model moves oil between particles): oil from half on.
// Every oil measure (spill metrics, pictures, node types, scores) uses it.
constexpr double kOilFractionThreshold = 0.5;
inline bool is_oil(Real oil_fraction) {
  return oil_fraction >= Real(kOilFractionThreshold);
}

// Axis-aligned box.
struct Aabb {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
  bool contains(const Vec3& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
};

}  // namespace sph
