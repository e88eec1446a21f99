#include "sph/river/river_generator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

namespace sph {

namespace {

constexpr Real kPi = Real(3.14159265358979323846);

Real smoothstep(Real t) {
  t = std::clamp(t, Real(0), Real(1));
  return t * t * (3 - 2 * t);
}

// 1 inside [a, b], easing in over `ramp` after a and out over `ramp` before b.
Real window(Real x, Real a, Real b, Real ramp) {
  return smoothstep((x - a) / ramp) * (1 - smoothstep((x - (b - ramp)) / ramp));
}

// A uniform number in [0, 1) from the generator's bits: the same on every platform, unlike
// std::uniform_real_distribution.
Real unit(std::mt19937_64& rng) {
  return Real(double(rng() >> 11) * 0x1.0p-53);
}

}  // namespace

Real river_centreline_y(const RiverGeneratorConfig& c, Real x) {
  const Real a = Real(0.25) * c.length, b = Real(0.5) * c.length;
  if (x <= a || x >= b) return 0;
  const Real s = std::sin(kPi * (x - a) / (b - a));
  return c.bend_amplitude * s * s;
}

Real river_surface_width(const RiverGeneratorConfig& c, Real x) {
  const Real l = c.length, ramp = Real(0.08) * l;
  const Real factor = 1 + (c.narrowing - 1) * window(x, Real(0.5) * l, Real(0.75) * l, ramp) +
                      (c.widening - 1) * smoothstep((x - Real(0.75) * l) / ramp);
  return c.width * factor;
}

std::vector<std::pair<std::string, Real>> river_half_span_terms(const RiverGeneratorConfig& c) {
  const Real widest = c.width * std::max({Real(1), c.widening, c.narrowing});
  return {{"bend_amplitude", std::abs(c.bend_amplitude)},
          {"width", Real(0.5) * widest},
          {"bank_height", c.bank_slope * c.bank_height},
          {"floodplain", c.floodplain}};
}

Terrain generate_river(const RiverGeneratorConfig& c) {
  Terrain t;
  t.cell_size = c.cell_size;
  // Summed in Real in this order, as always: the grid's size must not move by a rounding.
  Real half_span = 0;
  for (const auto& term : river_half_span_terms(c)) half_span += term.second;
  t.nx = int(std::ceil(c.length / c.cell_size)) + 1;
  t.ny = 2 * int(std::ceil(half_span / c.cell_size)) + 1;
  t.origin_x = 0;
  t.origin_y = -c.cell_size * Real(t.ny / 2);
  t.height.assign(size_t(t.nx) * size_t(t.ny), 0);
  t.water.assign(t.height.size(), 0);

  // Bed roughness: a few plane waves of random direction, wavelength and phase, summed and
  // scaled to `bed_roughness` at most.
  std::mt19937_64 rng(std::uint64_t(c.seed));
  struct Wave {
    Real kx, ky, phase;
  };
  std::vector<Wave> waves(6);
  for (auto& w : waves) {
    const Real angle = 2 * kPi * unit(rng);
    const Real wavelength = c.width * (Real(0.25) + unit(rng));
    const Real k = 2 * kPi / wavelength;
    w = {k * std::cos(angle), k * std::sin(angle), 2 * kPi * unit(rng)};
  }
  const Real wave_scale = c.bed_roughness / Real(waves.size());

  for (int iy = 0; iy < t.ny; ++iy)
    for (int ix = 0; ix < t.nx; ++ix) {
      const Real x = t.origin_x + c.cell_size * Real(ix);
      const Real y = t.origin_y + c.cell_size * Real(iy);
      const Real half_width = Real(0.5) * river_surface_width(c, x);
      const Real d = std::abs(y - river_centreline_y(c, x));
      // Height of the trapezoid: the bank passes through the water line at d = half_width.
      const Real bank = (d - half_width) / c.bank_slope;
      Real z = std::clamp(bank, -c.depth, c.bank_height);
      if (bank < 0) {
        // Roughness on the wetted bed only, fading towards the water line so the banks keep
        // their slope.
        Real noise = 0;
        for (const auto& w : waves) noise += std::sin(w.kx * x + w.ky * y + w.phase);
        z += wave_scale * noise * std::min(Real(1), -bank / c.depth);
      }
      t.at(ix, iy) = z;
      t.water[size_t(iy) * size_t(t.nx) + size_t(ix)] = d < half_width ? 1 : 0;
    }
  return t;
}

}  // namespace sph
