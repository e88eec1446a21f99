#include "sph/neighbours/neighbourhood.h"

#include <omp.h>

#include <cmath>
#include <vector>

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

namespace {

// Kernel values and volume-weighted gradients of the pairs [begin, end) of particle i (at xi),
// whose neighbours are at x with volumes `volume`. The offsets are first gathered into
// contiguous arrays so that the kernel itself (a square root, a division and a few polynomials
// per pair) runs as SIMD over the pairs; evaluated pair by pair it stalled on the division's
// latency. Adds sum_j V_j W_ij to `density` and, when given, sum_j V_j grad W_ij to
// `gradient_sum`.
template <class Kernel>
void evaluate_pairs(const Kernel& kernel, const Vec3& xi, const Vec3* x, const Real* volume,
                    const Index* neighbours, Index begin, Index end, PairTable& table,
                    PairScratch& s, Real& density, Vec3* gradient_sum) {
  const size_t m = size_t(end - begin);
  s.fit(m);
  Real* dx = s.dx.data();
  Real* dy = s.dy.data();
  Real* dz = s.dz.data();
  Real* w = s.w.data();
  Real* g = s.g.data();
  for (size_t t = 0; t < m; ++t) {
    const Vec3& xj = x[neighbours[begin + Index(t)]];
    dx[t] = xi[0] - xj[0];
    dy[t] = xi[1] - xj[1];
    dz[t] = xi[2] - xj[2];
  }
#pragma omp simd
  for (size_t t = 0; t < m; ++t) {
    const Real r = std::sqrt(dx[t] * dx[t] + dy[t] * dy[t] + dz[t] * dz[t]);
    w[t] = kernel.value_and_radial_factor(r, g[t]);
  }
  for (size_t t = 0; t < m; ++t) {
    const Index k = begin + Index(t);
    const Real vj = volume[neighbours[k]];
    const Real scale = vj * g[t];
    table.value[k] = w[t];
    table.gradient[k] = Vec3(scale * dx[t], scale * dy[t], scale * dz[t]);
    if (gradient_sum) *gradient_sum += table.gradient[k];
    density += vj * w[t];
  }
}

}  // namespace

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
    const Real* volume = fluid.rest_volume.data();
    PairTable& ff = this->fluid;
    PairTable& fb = this->boundary;
    scratch_.resize(size_t(omp_get_max_threads()));
#pragma omp parallel
    {
      PairScratch& scratch = scratch_[size_t(omp_get_thread_num())];
#pragma omp for schedule(dynamic, 64)
      for (long li = 0; li < long(n); ++li) {
        const Index i = Index(li);
        Real density = volume[i] * w_zero_;
        Vec3 boundary_sum = Vec3::Zero();
        evaluate_pairs(w, x[i], x, volume, ff.lists.indices.data(), ff.lists.offsets[i],
                       ff.lists.offsets[i + 1], ff, scratch, density, nullptr);
        evaluate_pairs(w, x[i], boundary.position.data(), boundary_volume_.data(),
                       fb.lists.indices.data(), fb.lists.offsets[i], fb.lists.offsets[i + 1], fb,
                       scratch, density, &boundary_sum);
        boundary_gradient_sum[i] = boundary_sum;
        fluid.density[i] = density;
      }
    }
    return 0;
  });
}

}  // namespace sph
