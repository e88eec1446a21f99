#include "farfield/model/drift.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "farfield/model/random_stream.h"

namespace farfield {

namespace {
constexpr double kGravity = 9.81;

// The cube root of h > 0 to 1e-14 relative: a first guess from the exponent's bits (the biased
// exponent divided by 3, its bias restored), then two of Halley's cubic steps. About 3x faster
// than glibc's std::cbrt; the drift takes one per flow sample, some twenty per element and step.
double cube_root(double h) {
  std::uint64_t bits;
  std::memcpy(&bits, &h, sizeof bits);
  bits = bits / 3 + 0x2A9F7893782DA1CEull;
  double y;
  std::memcpy(&y, &bits, sizeof y);
  for (int k = 0; k < 2; ++k) {
    const double y3 = y * y * y;
    y *= (y3 + 2 * h) / (2 * y3 + h);
  }
  return y;
}

// Manning's friction as a drag coefficient, tau / rho = (Cf / 2) |u| u: the square root of
// Cf / 2 = g n^2 / h^(1/3), which the log law's factor and the shear velocity take.
double root_half_drag(const FlowSample& s) {
  return std::sqrt(kGravity * s.manning * s.manning / cube_root(s.depth));
}

// The surface velocity alone: what the advection's sub-steps take, two samples each. Without
// the flow's direction and mixing coefficients (two divisions and a square root that only the
// end of a step needs), a sub-step's chain of dependent operations is shorter.
void surface_velocity(const FlowSample& s, const DriftSettings& settings, double& u, double& v) {
  if (s.where != FlowWhere::water || s.depth <= 0) {
    u = v = 0;
    return;
  }
  const double factor = settings.log_law ? 1 + root_half_drag(s) / settings.kappa : 1.0;
  u = factor * s.u;
  v = factor * s.v;
}

bool is_water(const FlowSample& s, double min_depth) {
  return s.where == FlowWhere::water && s.depth >= min_depth;
}

// The mixing tensor's components (D_xx, D_xy, D_yy) at a point; zero off the water.
void diffusivity(const SurfaceFlow& flow, const DriftSettings& settings, double x, double y,
                 double t, double& dxx, double& dxy, double& dyy) {
  const FlowSample s = flow.sample(x, y, t);
  if (s.where != FlowWhere::water) {
    dxx = dxy = dyy = 0;
    return;
  }
  const LocalDrift d = local_drift(s, settings);
  dxx = d.d_along * d.ex * d.ex + d.d_across * d.ey * d.ey;
  dxy = (d.d_along - d.d_across) * d.ex * d.ey;
  dyy = d.d_along * d.ey * d.ey + d.d_across * d.ex * d.ex;
}
}  // namespace

// Moves (nx, ny), a point past the water's edge reached from (x, y), back onto the water by
// removing the part of its displacement that runs into the bank; the bank's normal is the
// depth's gradient at (x, y). False (and nothing changed) when that lands on no water either.
bool slide_along_bank(const SurfaceFlow& flow, double grid_cell, double min_depth, double t,
                      double x, double y, double& nx, double& ny, FlowSample& landed) {
  const double delta = 0.5 * grid_cell;
  const auto depth = [&](double px, double py) {
    const FlowSample s = flow.sample(px, py, t);
    return s.where == FlowWhere::outside ? 0.0 : s.depth;
  };
  double gx = depth(x + delta, y) - depth(x - delta, y);
  double gy = depth(x, y + delta) - depth(x, y - delta);
  const double g = std::sqrt(gx * gx + gy * gy);
  if (!(g > 0)) return false;
  gx /= g;
  gy /= g;
  const double dx = nx - x, dy = ny - y;
  const double into = dx * gx + dy * gy;  // < 0: towards the shallows
  if (into >= 0) return false;
  const double sx = x + dx - into * gx, sy = y + dy - into * gy;
  const FlowSample s = flow.sample(sx, sy, t);
  if (!is_water(s, min_depth)) return false;
  nx = sx;
  ny = sy;
  landed = s;
  return true;
}

double shear_velocity(const FlowSample& s) {
  if (s.where != FlowWhere::water || s.depth <= 0) return 0;
  return std::sqrt(s.u * s.u + s.v * s.v) * root_half_drag(s);
}

LocalDrift local_drift(const FlowSample& s, const DriftSettings& settings) {
  LocalDrift d;
  if (s.where != FlowWhere::water || s.depth <= 0) return d;
  const double speed = std::sqrt(s.u * s.u + s.v * s.v);
  const double root_half_cf = root_half_drag(s);
  const double shear = speed * root_half_cf;
  const double factor = settings.log_law ? 1 + root_half_cf / settings.kappa : 1.0;
  d.u = factor * s.u;
  d.v = factor * s.v;
  if (speed > 0) {
    d.ex = s.u / speed;
    d.ey = s.v / speed;
  }
  if (settings.mixing) {
    d.d_along = settings.longitudinal_mixing * s.depth * shear + settings.min_diffusivity;
    d.d_across = settings.transverse_mixing * s.depth * shear + settings.min_diffusivity;
  }
  return d;
}

DriftResult drift_element(const SurfaceFlow& flow, const DriftSettings& settings, const Wind& wind,
                          bool ice, double grid_cell, double min_depth, double t, double dt,
                          std::uint64_t step, std::uint64_t element, double x, double y,
                          const BankFull& bank_full, double spread_x, double spread_y) {
  DriftResult r;
  r.x = r.wet_x = x;
  r.y = r.wet_y = y;
  const double wind_u = ice ? 0.0 : settings.wind_factor * wind.east;
  const double wind_v = ice ? 0.0 : settings.wind_factor * wind.north;
  FlowSample here = flow.sample(x, y, t);
  if (!is_water(here, min_depth)) {
    r.where = here.where == FlowWhere::outside ? FlowWhere::outside : FlowWhere::bank;
    return r;
  }
  double here_u, here_v;
  surface_velocity(here, settings, here_u, here_v);
  // The advection in sub-steps of at most max_cells_per_substep cells at the starting speed.
  const double u0 = here_u + wind_u, v0 = here_v + wind_v;
  const int substeps = std::max(1, int(std::ceil(std::sqrt(u0 * u0 + v0 * v0) * dt /
                                                 (settings.max_cells_per_substep * grid_cell))));
  const double h = dt / substeps;
  const auto stop_at = [&](const FlowSample& s, double nx, double ny) {
    r.x = nx;
    r.y = ny;
    r.where = s.where == FlowWhere::outside ? FlowWhere::outside : FlowWhere::bank;
  };
  for (int k = 0; k < substeps; ++k) {
    const double tk = t + k * h;
    const double ua = here_u + wind_u, va = here_v + wind_v;
    double ub = ua, vb = va;
    const FlowSample mid = flow.sample(x + 0.5 * h * ua, y + 0.5 * h * va, tk + 0.5 * h);
    if (is_water(mid, min_depth)) {
      surface_velocity(mid, settings, ub, vb);
      ub += wind_u;
      vb += wind_v;
    }
    double nx = x + h * ub, ny = y + h * vb;
    here = flow.sample(nx, ny, tk + h);
    if (!is_water(here, min_depth)) {
      if (here.where == FlowWhere::outside || !bank_full || !bank_full(x, y)) {
        stop_at(here, nx, ny);
        return r;
      }
      // A bank that holds no more: the element moves on along it, its motion into the bank
      // removed (the bank's normal from the depth's gradient), or stays where it is.
      if (!slide_along_bank(flow, grid_cell, min_depth, tk + h, x, y, nx, ny, here)) {
        nx = x;
        ny = y;
        here = flow.sample(x, y, tk + h);
      }
    }
    surface_velocity(here, settings, here_u, here_v);
    x = r.x = r.wet_x = nx;
    y = r.y = r.wet_y = ny;
  }
  // The mixing: one Gaussian step of the whole dt (its variance 2 D dt is exact for any dt
  // where D is uniform), with the drift div(D) by central differences over half a cell; and the
  // spreading's displacement with it.
  if (settings.mixing || spread_x != 0 || spread_y != 0) {
    const double te = t + dt;
    double nx = x + spread_x, ny = y + spread_y;
    if (settings.mixing) {
      const LocalDrift d = local_drift(here, settings);
      const double delta = 0.5 * grid_cell;
      double xx_e, xy_e, yy_e, xx_w, xy_w, yy_w, xx_n, xy_n, yy_n, xx_s, xy_s, yy_s;
      diffusivity(flow, settings, x + delta, y, te, xx_e, xy_e, yy_e);
      diffusivity(flow, settings, x - delta, y, te, xx_w, xy_w, yy_w);
      diffusivity(flow, settings, x, y + delta, te, xx_n, xy_n, yy_n);
      diffusivity(flow, settings, x, y - delta, te, xx_s, xy_s, yy_s);
      const double div_x = (xx_e - xx_w + xy_n - xy_s) / (2 * delta);
      const double div_y = (xy_e - xy_w + yy_n - yy_s) / (2 * delta);
      CounterRandom random(settings.seed, step, element, 0);
      double a, b;
      random.normal_pair(a, b);
      const double along = std::sqrt(2 * d.d_along * dt) * a;
      const double across = std::sqrt(2 * d.d_across * dt) * b;
      nx += div_x * dt + along * d.ex - across * d.ey;
      ny += div_y * dt + along * d.ey + across * d.ex;
    }
    const FlowSample end = flow.sample(nx, ny, te);
    if (!is_water(end, min_depth)) {
      if (end.where != FlowWhere::outside && bank_full && bank_full(x, y)) {
        r.where = FlowWhere::water;  // a full bank: the mixing's step is not taken
        return r;
      }
      stop_at(end, nx, ny);
      return r;
    }
    r.x = r.wet_x = nx;
    r.y = r.wet_y = ny;
  }
  r.where = FlowWhere::water;
  return r;
}

}  // namespace farfield
