#include "sph/simulation/density_relaxation.h"

#include <algorithm>

#include "sph/solvers/pressure_terms.h"

namespace sph {

DensityRelaxation::DensityRelaxation(const SceneConfig& scene)
    : reference_(scene),
      volume_(particle_rest_volume(scene)),
      neighbourhood_(reference_.domain(), kernel_kind(scene.kernel), scene.support_radius(),
                     reference_.boundary()) {}

FluidParticles DensityRelaxation::fluid_of(const std::vector<Vec3>& positions,
                                           const std::vector<Real>& oil_fraction,
                                           std::vector<size_t>& inside) {
  const MaterialsConfig& m = reference_.scene().materials;
  const Aabb& domain = reference_.domain();
  FluidParticles fluid;
  inside.clear();
  for (size_t i = 0; i < positions.size(); ++i) {
    const Vec3& x = positions[i];
    if (!x.allFinite() || (x.array() < domain.min.array()).any() ||
        (x.array() > domain.max.array()).any())
      continue;
    inside.push_back(i);
    fluid.add(x, Vec3::Zero(), volume_,
              mix_phases(oil_fraction[i], m.water.density, m.water.viscosity, m.oil.density,
                         m.oil.viscosity));
  }
  neighbourhood_.update(fluid, reference_.boundary());
  return fluid;
}

CompressionStats DensityRelaxation::compression(const FluidParticles& fluid) const {
  CompressionStats s;
  std::vector<double> errors;
  for (Index i = 0; i < fluid.active_count(); ++i)
    errors.push_back(std::max(double(fluid.density[i]) - 1.0, 0.0));
  s.particles = long(errors.size());
  if (errors.empty()) return s;
  for (double e : errors) s.mean += e / double(errors.size());
  std::sort(errors.begin(), errors.end());
  s.p95 = errors[std::min(errors.size() - 1, size_t(0.95 * double(errors.size())))];
  s.max = errors.back();
  return s;
}

CompressionStats DensityRelaxation::measure(const std::vector<Vec3>& positions,
                                            const std::vector<Real>& oil_fraction) {
  std::vector<size_t> inside;
  return compression(fluid_of(positions, oil_fraction, inside));
}

std::pair<CompressionStats, CompressionStats> DensityRelaxation::relax(
    std::vector<Vec3>& positions, const std::vector<Real>& oil_fraction, int iterations) {
  std::vector<size_t> inside;
  FluidParticles fluid = fluid_of(positions, oil_fraction, inside);
  const CompressionStats before = compression(fluid);
  const Index n = fluid.active_count();
  for (int k = 0; k < iterations && n > 0; ++k) {
    if (k > 0) neighbourhood_.update(fluid, reference_.boundary());
    pressure_terms::density_ratios(fluid, reference_.scene().materials.water.density, ratio_);
    alpha_.resize(size_t(n));
    s_.resize(size_t(n));
    pressure_terms::compute_factors(neighbourhood_, ratio_, n, alpha_);
    for (Index i = 0; i < n; ++i)
      s_[size_t(i)] = std::max(fluid.density[i] - Real(1), Real(0)) * alpha_[size_t(i)];
    // dt = 1: the velocity change of a unit step is the position change of any step. A particle
    // the correction would push out of the domain stops at its edge (the next search needs it
    // inside; a strongly compressed learned frame near an open top can push one out).
    const Aabb& domain = reference_.domain();
    pressure_terms::stiffness_velocity_change(
        neighbourhood_, s_, ratio_, Real(1), n, [&](Index i, const Vec3& dx) {
          fluid.position[i] = (fluid.position[i] + dx).cwiseMax(domain.min).cwiseMin(domain.max);
        });
  }
  if (iterations > 0 && n > 0) neighbourhood_.update(fluid, reference_.boundary());
  const CompressionStats after = compression(fluid);
  // The particle set keeps the active ones in the order they were added.
  for (size_t k = 0; k < inside.size(); ++k) positions[inside[k]] = fluid.position[Index(k)];
  return {before, after};
}

}  // namespace sph
