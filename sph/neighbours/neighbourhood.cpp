#include "sph/neighbours/neighbourhood.h"

namespace sph {

ParticleNeighbourhood::ParticleNeighbourhood(const Aabb& domain, KernelKind kernel,
                                             Real support_radius, const BoundaryParticles& boundary)
    : kernel_(kernel),
      support_radius_(support_radius),
      w_zero_(with_kernel(kernel, support_radius, [](const auto& w) { return w.value(Real(0)); })),
      boundary_volume_(boundary.volume),
      fluid_grid_(domain, support_radius),
      boundary_grid_(domain, support_radius) {
  boundary_grid_.build(boundary.position);
}

void ParticleNeighbourhood::update(FluidParticles& fluid, const BoundaryParticles& boundary) {
  const Index n = fluid.active_count();
  fluid_grid_.build(fluid.position.data(), n);
  fluid_grid_.find(fluid.position.data(), n, /*same_set=*/true, this->fluid.lists);
  boundary_grid_.find(fluid.position.data(), n, /*same_set=*/false, this->boundary.lists);
  update_pair_kernels(fluid, boundary);
}

void ParticleNeighbourhood::update_pair_kernels(FluidParticles& fluid,
                                                const BoundaryParticles& boundary) {
  const Index n = fluid.active_count();
  this->fluid.value.resize(this->fluid.lists.pairs());
  this->fluid.gradient.resize(this->fluid.lists.pairs());
  this->boundary.value.resize(this->boundary.lists.pairs());
  this->boundary.gradient.resize(this->boundary.lists.pairs());
  boundary_gradient_sum.resize(n);

  with_kernel(kernel_, support_radius_, [&](const auto& w) {
    const Vec3* x = fluid.position.data();
    const Vec3* xb = boundary.position.data();
    const Real* volume = fluid.rest_volume.data();
    const Real* volume_b = boundary_volume_.data();
    PairTable& ff = this->fluid;
    PairTable& fb = this->boundary;
#pragma omp parallel for schedule(dynamic, 64)
    for (long li = 0; li < long(n); ++li) {
      const Index i = Index(li);
      Real density = volume[i] * w_zero_;
      for (Index k = ff.lists.offsets[i]; k < ff.lists.offsets[i + 1]; ++k) {
        const Index j = ff.lists.indices[k];
        const Vec3 r = x[i] - x[j];
        Vec3 grad;
        const Real wij = w.value_and_gradient(r, grad);
        ff.value[k] = wij;
        ff.gradient[k] = volume[j] * grad;
        density += volume[j] * wij;
      }
      Vec3 grad_sum = Vec3::Zero();
      for (Index k = fb.lists.offsets[i]; k < fb.lists.offsets[i + 1]; ++k) {
        const Index b = fb.lists.indices[k];
        const Vec3 r = x[i] - xb[b];
        Vec3 grad;
        const Real wib = w.value_and_gradient(r, grad);
        fb.value[k] = wib;
        fb.gradient[k] = volume_b[b] * grad;
        grad_sum += fb.gradient[k];
        density += volume_b[b] * wib;
      }
      boundary_gradient_sum[i] = grad_sum;
      fluid.density[i] = density;
    }
    return 0;
  });
}

}  // namespace sph
