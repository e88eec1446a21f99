#include "sph/forces/surface_tension_force.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "sph/core/lattice.h"
#include "sph/core/particle_loops.h"

namespace sph {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Neighbours of a particle inside a cubic lattice of `spacing` within `radius` (itself excluded).
Index full_neighbour_count(Real spacing, Real radius) {
  const int reach = int(std::ceil(radius / spacing));
  Index count = 0;
  for (int x = -reach; x <= reach; ++x)
    for (int y = -reach; y <= reach; ++y)
      for (int z = -reach; z <= reach; ++z) {
        const Real r2 = spacing * spacing * Real(x * x + y * y + z * z);
        if (r2 > 0 && r2 < radius * radius) ++count;
      }
  return count;
}

// Entries of the pair law table over u = (r / h)^2 in [0, 1]: 1,024 intervals keep linear
// interpolation within 0.1 % of the law for r > 0.1 h (the closest pairs are near half the
// support radius) and the table in 4 KB of L1 cache.
constexpr int kLawIntervals = 1024;

}  // namespace

Real tension_per_strength(KernelKind kernel, Real support_radius, Real spacing, Real volume,
                          Real reference_density) {
  const double h = double(support_radius), d = double(spacing);
  // psi(r) = int_r^h cos(3 pi r' / 2h) W(r') dr', the pair potential per rho_ref s V^2, by
  // Simpson's rule on a table over [0, h].
  constexpr int kSteps = 2000;
  std::vector<double> psi(kSteps + 1, 0.0);
  with_kernel(kernel, support_radius, [&](const auto& w) {
    auto f = [&](double r) { return std::cos(1.5 * kPi * r / h) * double(w.value(Real(r))); };
    const double dr = h / kSteps;
    for (int k = kSteps - 1; k >= 0; --k) {
      const double a = k * dr;
      psi[size_t(k)] = psi[size_t(k + 1)] + dr / 6 * (f(a) + 4 * f(a + dr / 2) + f(a + dr));
    }
    return 0;
  });
  auto psi_at = [&](double r) {
    const double t = std::min(r / h, 1.0) * kSteps;
    const int k = std::min(int(t), kSteps - 1);
    return psi[size_t(k)] + (t - k) * (psi[size_t(k + 1)] - psi[size_t(k)]);
  };
  // One column of the lattice above the plane z = 0 (centres at d/2, 3d/2, ...) against every
  // particle below it (-d/2, -3d/2, ...) within reach: the pairs crossing an area d^2.
  const int reach = int(std::ceil(h / d)) + 1;
  double sum = 0;
  for (int above = 0; above < reach; ++above)
    for (int below = 0; below < reach; ++below)
      for (int x = -reach; x <= reach; ++x)
        for (int y = -reach; y <= reach; ++y) {
          const double dz = (above + below + 1) * d;
          const double r = std::sqrt(dz * dz + (x * x + y * y) * d * d);
          if (r < h) sum += psi_at(r);
        }
  return Real(-double(reference_density) * double(volume) * double(volume) * sum / (2 * d * d));
}

PairStrengths pair_strengths(const SurfaceTensionConfig& c, Real lambda) {
  return {c.water_air / lambda, c.oil_air / lambda,
          (c.water_air + c.oil_air - c.oil_water) / (2 * lambda)};
}

void SurfaceTensionForce::tabulate_pair_law(KernelKind kernel, Real support_radius) {
  law_kernel_ = kernel;
  law_support_radius_ = support_radius;
  law_.resize(kLawIntervals + 1);
  const double h = double(support_radius);
  with_kernel(kernel, support_radius, [&](const auto& w) {
    for (int e = 0; e <= kLawIntervals; ++e) {
      // At u = 0 the law is singular (W / r); its first entry takes the value at u = 1/4 of an
      // interval, a distance no two particles come to.
      const double u = e == 0 ? 0.25 / kLawIntervals : double(e) / kLawIntervals;
      const double r = h * std::sqrt(u);
      law_[size_t(e)] = Real(std::cos(1.5 * kPi * r / h) * double(w.value(Real(r))) / r);
    }
  });
  law_scale_ = Real(kLawIntervals) / (support_radius * support_radius);
  const Real volume = lattice_rest_volume(kernel, support_radius, spacing_);
  strengths_ = pair_strengths(
      config_, tension_per_strength(kernel, support_radius, spacing_, volume, reference_density_));
}

NonPressureForceEntry SurfaceTensionForce::entry() {
  return {"surface_tension",
          {common::ConfigSectionEntry::of<SurfaceTensionConfig>(
              "surface_tension", "Cosine-force surface tension (solver mtdf only)")},
          [](const PhysicsContext&) { return false; },
          [](const PhysicsContext& physics) -> std::unique_ptr<NonPressureForce> {
            return std::make_unique<SurfaceTensionForce>(
                physics.settings<SurfaceTensionConfig>("surface_tension"),
                physics.particle_diameter(), physics.support_radius,
                physics.materials.water.density);
          }};
}

SurfaceTensionForce::SurfaceTensionForce(const SurfaceTensionConfig& config, Real particle_spacing,
                                         Real support_radius, Real reference_density)
    : config_(config),
      reference_density_(reference_density),
      spacing_(particle_spacing),
      surface_neighbour_count_(
          Index(config.surface_neighbour_fraction *
                Real(full_neighbour_count(particle_spacing, support_radius)))) {}

void SurfaceTensionForce::add_acceleration(FluidParticles& fluid, const BoundaryParticles& boundary,
                                           const ParticleNeighbourhood& nb, Real) {
  if (law_.empty() || law_kernel_ != nb.kernel() || law_support_radius_ != nb.support_radius())
    tabulate_pair_law(nb.kernel(), nb.support_radius());
  const Real* law = law_.data();
  const Real scale = law_scale_;
  // cos(3 pi r / 2h) W(r) / r from the table, linear in r^2: no square root, division or
  // cosine per pair, which made this pass cost as much as the viscosity.
  const auto pair_law = [law, scale](Real r2) {
    const Real t = std::min(r2 * scale, Real(kLawIntervals));
    const int e = std::min(int(t), kLawIntervals - 1);
    const Real f = t - Real(e);
    return law[e] + f * (law[e + 1] - law[e]);
  };
  const Vec3* x = fluid.position.data();
  const ParticleType* type = fluid.type.data();
  const Real s_water = strengths_.water, s_oil = strengths_.oil, s_mixed = strengths_.oil_water;
  const Real s_wall = config_.boundary;
  for_each_active(fluid, [&](Index i) {
    const auto& ff = nb.fluid;
    const Index begin = ff.lists.offsets[i], end = ff.lists.offsets[i + 1];
    if (config_.surface_only) {
      bool acts = end - begin + nb.boundary.lists.count(i) < surface_neighbour_count_;
      for (Index k = begin; k < end && !acts; ++k) acts = type[ff.lists.indices[k]] != type[i];
      if (!acts) return;
    }
    Vec3 a = Vec3::Zero();
    for (Index k = begin; k < end; ++k) {
      const Index j = ff.lists.indices[k];
      const Vec3 xij = x[i] - x[j];
      const Real s = type[j] != type[i] ? s_mixed : type[i] == ParticleType::kOil ? s_oil : s_water;
      a += (s * fluid.rest_volume[j] * pair_law(xij.squaredNorm())) * xij;
    }
    if (s_wall != 0) {
      nb.boundary.for_each(i, [&](Index b, Index) {
        const Vec3 xib = x[i] - boundary.position[b];
        a += (s_wall * boundary.volume[b] * pair_law(xib.squaredNorm())) * xib;
      });
    }
    fluid.acceleration[i] += (reference_density_ / fluid.rest_density[i]) * a;
  });
}

}  // namespace sph
