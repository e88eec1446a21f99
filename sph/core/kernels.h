#pragma once
// SPH smoothing kernels in 3D. Each kernel carries its support radius h (W = 0 for r >= h).
//
// CubicSplineKernel: Monaghan's cubic B-spline, written on the support radius as in
//   Bender & Koschier, "Divergence-free SPH for incompressible and turbulent flows", SCA 2015.
// WendlandC2Kernel: Wendland, "Piecewise polynomial, positive definite and compactly supported
//   radial functions of minimal degree", Adv. Comput. Math. 4 (1995); 3D C2 form as in
//   Dehnen & Aly, MNRAS 425 (2012), table 1.

#include <algorithm>
#include <cmath>
#include <string>

#include "sph/core/types.h"

namespace sph {

class CubicSplineKernel {
 public:
  explicit CubicSplineKernel(Real support_radius)
      : h_(support_radius),
        inv_h_(Real(1) / support_radius),
        k_(Real(8.0 / M_PI) / (support_radius * support_radius * support_radius)),
        l_(Real(48.0 / M_PI) / (support_radius * support_radius * support_radius)) {}

  Real support_radius() const { return h_; }

  Real value(Real r) const {
    const Real q = r * inv_h_;
    if (q >= Real(1)) return Real(0);
    if (q <= Real(0.5)) return k_ * (Real(6) * q * q * q - Real(6) * q * q + Real(1));
    const Real s = Real(1) - q;
    return k_ * Real(2) * s * s * s;
  }
  Real value(const Vec3& r) const { return value(r.norm()); }

  // Gradient with respect to x_i of W(x_i - x_j), given r = x_i - x_j.
  Vec3 gradient(const Vec3& r) const {
    Vec3 g;
    value_and_gradient(r, g);
    return g;
  }

  // W(r) and its gradient with one square root (the neighbourhood evaluates both for each pair).
  Real value_and_gradient(const Vec3& r, Vec3& gradient) const {
    Real g;
    const Real w = value_and_radial_factor(r.norm(), g);
    gradient = g * r;
    return w;
  }

  // W at distance r and the factor g with grad W(x_i - x_j) = g (x_i - x_j); g is 0 where the
  // gradient is undefined (r ~ 0) and both are 0 beyond the support. No branches: the
  // neighbourhood calls it in loops over many pairs that the compiler turns into SIMD.
  Real value_and_radial_factor(Real rl, Real& g) const {
    const Real q = std::min(rl * inv_h_, Real(1));
    const Real s = Real(1) - q;
    // Both pieces are evaluated and one is selected, so the loop has no branches to vectorize.
    const Real w_inner = k_ * (Real(6) * q * q * q - Real(6) * q * q + Real(1));
    const Real w_outer = k_ * Real(2) * s * s * s;
    const Real dw_inner = l_ * q * (Real(3) * q - Real(2));
    const Real dw_outer = -l_ * s * s;
    const bool inner = q <= Real(0.5);
    const Real tiny = Real(1e-9) * h_;
    const Real dw_dr_over_r = (inner ? dw_inner : dw_outer) * inv_h_ / std::max(rl, tiny);
    g = rl > tiny ? dw_dr_over_r : Real(0);
    return inner ? w_inner : w_outer;
  }

 private:
  Real h_, inv_h_, k_, l_;
};

class WendlandC2Kernel {
 public:
  explicit WendlandC2Kernel(Real support_radius)
      : h_(support_radius),
        inv_h_(Real(1) / support_radius),
        k_(Real(21.0 / (2.0 * M_PI)) / (support_radius * support_radius * support_radius)) {}

  Real support_radius() const { return h_; }

  Real value(Real r) const {
    const Real q = r * inv_h_;
    if (q >= Real(1)) return Real(0);
    const Real s = Real(1) - q;
    const Real s2 = s * s;
    return k_ * s2 * s2 * (Real(1) + Real(4) * q);
  }
  Real value(const Vec3& r) const { return value(r.norm()); }

  Vec3 gradient(const Vec3& r) const {
    Vec3 g;
    value_and_gradient(r, g);
    return g;
  }

  Real value_and_gradient(const Vec3& r, Vec3& gradient) const {
    Real g;
    const Real w = value_and_radial_factor(r.norm(), g);
    gradient = g * r;
    return w;
  }

  // As CubicSplineKernel::value_and_radial_factor.
  Real value_and_radial_factor(Real rl, Real& g) const {
    const Real q = std::min(rl * inv_h_, Real(1));
    const Real s = Real(1) - q;
    const Real s3 = s * s * s;
    const Real tiny = Real(1e-9) * h_;
    const Real dw_dr_over_r = -Real(20) * k_ * q * s3 * inv_h_ / std::max(rl, tiny);
    g = rl > tiny ? dw_dr_over_r : Real(0);
    return k_ * s3 * s * (Real(1) + Real(4) * q);
  }

 private:
  Real h_, inv_h_, k_;
};

// The kernels a scene can choose by name.
enum class KernelKind { kCubicSpline, kWendlandC2 };

// The kernel a scene's `kernel` value names ("wendland_c2"; anything else is the cubic spline:
// the scene's schema admits only the two).
inline KernelKind kernel_kind(const std::string& name) {
  return name == "wendland_c2" ? KernelKind::kWendlandC2 : KernelKind::kCubicSpline;
}

// Calls f(kernel) with the concrete kernel type, so hot loops are compiled per kernel instead of
// paying for a virtual call per pair.
template <class F>
decltype(auto) with_kernel(KernelKind kind, Real support_radius, F&& f) {
  if (kind == KernelKind::kWendlandC2) return f(WendlandC2Kernel(support_radius));
  return f(CubicSplineKernel(support_radius));
}

}  // namespace sph
