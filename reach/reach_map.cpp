#include "reach/reach_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "common/bitmap_font.h"
#include "common/drawing.h"
#include "common/picture_annotation.h"

namespace reach {

namespace {

using common::Rgb;

constexpr Rgb kInk{30, 30, 30};
constexpr Rgb kArrow{255, 255, 255};
constexpr int kPad = 8;

Rgb mix(Rgb a, Rgb b, double t) {
  t = std::clamp(t, 0.0, 1.0);
  const auto m = [&](int x, int y) { return std::uint8_t(std::lround(x + (y - x) * t)); };
  return {m(a.r, b.r), m(a.g, b.g), m(a.b, b.b)};
}

// Shallow water light blue, deep water dark blue.
Rgb water_colour(double depth, double scale) {
  return mix({170, 210, 245}, {10, 40, 130}, std::sqrt(std::max(0.0, depth) / scale));
}

// Terrain in earth tones by height, shaded from the north-west (azimuth 315 deg, 45 deg high),
// its slopes exaggerated `relief` times (a river valley is too flat to shade at 1:1).
Rgb terrain_colour(const Grid& g, const Field& bed, int i, int j, double lo, double hi,
                   double relief) {
  const auto z = [&](int a, int b) {
    a = std::clamp(a, 0, g.nx - 1), b = std::clamp(b, 0, g.ny - 1);
    const double v = bed[g.at(a, b)];
    return std::isnan(v) ? bed[g.at(i, j)] : v;
  };
  const double zx = relief * (z(i + 1, j) - z(i - 1, j)) / (2 * g.dx);
  const double zy = relief * (z(i, j + 1) - z(i, j - 1)) / (2 * g.dy);
  // The light's direction (x east, y north, z up) and the surface normal (-zx, -zy, 1).
  const double lx = -std::sqrt(0.25), ly = std::sqrt(0.25), lz = std::sqrt(0.5);
  const double shade = std::max(0.0, (-zx * lx - zy * ly + lz) / std::sqrt(zx * zx + zy * zy + 1));
  const double height = hi > lo ? (bed[g.at(i, j)] - lo) / (hi - lo) : 0.5;
  const Rgb base = mix({120, 150, 95}, {200, 180, 140}, height);
  return mix({40, 40, 40}, base, 0.35 + 0.65 * shade);
}

// The exaggeration that gives the terrain's 90th-percentile slope a gradient of 0.3, between 1
// and 50.
double relief_of(const Grid& g, const Field& bed) {
  std::vector<double> slopes;
  for (int j = 1; j + 1 < g.ny; j += 2)
    for (int i = 1; i + 1 < g.nx; i += 2) {
      const double zx = (bed[g.at(i + 1, j)] - bed[g.at(i - 1, j)]) / (2 * g.dx);
      const double zy = (bed[g.at(i, j + 1)] - bed[g.at(i, j - 1)]) / (2 * g.dy);
      const double s = std::hypot(zx, zy);
      if (std::isfinite(s)) slopes.push_back(s);
    }
  if (slopes.empty()) return 1.0;
  const size_t k = slopes.size() * 9 / 10;
  std::nth_element(slopes.begin(), slopes.begin() + long(k), slopes.end());
  return slopes[k] > 0 ? std::clamp(0.3 / slopes[k], 1.0, 50.0) : 1.0;
}

}  // namespace

std::string duration_label(double seconds) {
  const long total = long(std::lround(seconds));
  const long h = total / 3600, m = (total % 3600) / 60, s = total % 60;
  char text[64];
  if (h > 0)
    std::snprintf(text, sizeof text, "t = %ld h %02ld min %02ld s", h, m, s);
  else if (m > 0)
    std::snprintf(text, sizeof text, "t = %ld min %02ld s", m, s);
  else
    std::snprintf(text, sizeof text, "t = %.1f s", seconds);
  return text;
}

MapFrame reach_map_frame(const Grid& g, int max_width) {
  // Pixels per cell (a whole number), or cells per pixel when the grid is wider than allowed.
  const double cells_per_pixel = g.nx > max_width ? double(g.nx) / max_width : 0.0;
  const int per_cell = cells_per_pixel > 0 ? 1 : std::max(1, max_width / g.nx);
  MapFrame f;
  f.width = cells_per_pixel > 0 ? max_width : g.nx * per_cell;
  const double cell_of_pixel = cells_per_pixel > 0 ? cells_per_pixel : 1.0 / per_cell;
  f.height = int(std::lround(g.ny / cell_of_pixel * (g.dy / g.dx)));
  f.metres_per_pixel = g.dx * cell_of_pixel;
  f.band_top = f.height;
  f.band_height = 4 * kPad + 3 * common::kGlyphHeight * common::kAnnotationTextScale;
  f.x0 = g.x0;
  f.y0 = g.y0;
  return f;
}

common::RgbImage draw_reach_map(const Grid& g, const Field& bed, const WaterState& w, double time_s,
                                double depth_scale, double speed_scale, double dry_depth,
                                int max_width) {
  const MapFrame frame = reach_map_frame(g, max_width);
  const int width = frame.width, height = frame.height;
  double lo = 1e300, hi = -1e300;
  for (double z : bed)
    if (!std::isnan(z)) lo = std::min(lo, z), hi = std::max(hi, z);
  const double relief = relief_of(g, bed);

  common::RgbImage img;
  img.width = width;
  img.height = height + frame.band_height;
  img.pixels.assign(size_t(img.width) * size_t(img.height) * 3, 255);
  const double metres_per_pixel = frame.metres_per_pixel;
  const auto cell_at = [&](int px, int py, int& i, int& j) {
    i = std::clamp(int((px + 0.5) * metres_per_pixel / g.dx), 0, g.nx - 1);
    j = std::clamp(g.ny - 1 - int((py + 0.5) * metres_per_pixel / g.dy), 0, g.ny - 1);
  };
  for (int py = 0; py < height; ++py)
    for (int px = 0; px < width; ++px) {
      int i, j;
      cell_at(px, py, i, j);
      const size_t c = g.at(i, j);
      Rgb colour{255, 255, 255};
      if (!std::isnan(bed[c])) {
        colour = terrain_colour(g, bed, i, j, lo, hi, relief);
        if (w.h[c] > dry_depth) colour = mix(colour, water_colour(w.h[c], depth_scale), 0.85);
      }
      common::put(img, px, py, colour);
    }

  // Arrows on a lattice about 28 pixels apart, the longest `speed_scale` long at 24 pixels.
  const int spacing = 28;
  for (int py = spacing / 2; py < height; py += spacing)
    for (int px = spacing / 2; px < width; px += spacing) {
      int i, j;
      cell_at(px, py, i, j);
      const size_t c = g.at(i, j);
      if (std::isnan(bed[c]) || w.h[c] <= 10 * dry_depth) continue;
      const double u = w.hu[c] / w.h[c], v = w.hv[c] / w.h[c];
      const double speed = std::hypot(u, v);
      if (speed < 0.05 * speed_scale) continue;
      const double len = 24 * std::min(1.0, speed / speed_scale);
      common::draw_arrow(img, float(px - 0.5 * len * u / speed), float(py + 0.5 * len * v / speed),
                         float(px + 0.5 * len * u / speed), float(py - 0.5 * len * v / speed),
                         kArrow);
    }

  // The band: time, scale bar and north on the first line; depth legend and arrow on the next.
  const int scale = common::kAnnotationTextScale;
  const int line = common::kGlyphHeight * scale + kPad;
  int y = height + kPad;
  common::draw_text(img, kPad, y, duration_label(time_s), scale, kInk);
  const double bar_m = common::scale_bar_length(width * metres_per_pixel);
  const int bar_px = int(std::lround(bar_m / metres_per_pixel));
  int x = kPad + common::text_width("t = 00 h 00 min 00 s", scale) + 3 * kPad;
  common::fill_rect(img, x, y + line / 2 - 2, bar_px, 4, kInk);
  common::fill_rect(img, x, y, 2, line - kPad, kInk);
  common::fill_rect(img, x + bar_px - 2, y, 2, line - kPad, kInk);
  char label[64];
  if (bar_m >= 1000)
    std::snprintf(label, sizeof label, "%g km", bar_m / 1000);
  else
    std::snprintf(label, sizeof label, "%g m", bar_m);
  x += bar_px + kPad;
  common::draw_text(img, x, y, label, scale, kInk);
  x += common::text_width(label, scale) + 3 * kPad;
  common::draw_arrow(img, float(x + 6), float(y + line - kPad), float(x + 6), float(y - 2), kInk);
  common::draw_text(img, x + 16, y, "n", scale, kInk);

  y += line + kPad / 2;
  x = kPad;
  common::draw_text(img, x, y, "depth", scale, kInk);
  x += common::text_width("depth", scale) + kPad;
  const int ramp = std::min(200, width / 3);
  for (int k = 0; k < ramp; ++k)
    common::fill_rect(img, x + k, y, 1, line - kPad,
                      water_colour(depth_scale * double(k) / (ramp - 1), depth_scale));
  std::snprintf(label, sizeof label, "0 - %.3g m", depth_scale);
  common::draw_text(img, x + ramp + kPad, y, label, scale, kInk);
  x += ramp + 2 * kPad + common::text_width(label, scale) + 2 * kPad;
  common::fill_rect(img, x - 4, y - 4, 24 + 8, line, {10, 40, 130});
  common::draw_arrow(img, float(x), float(y + (line - kPad) / 2), float(x + 24),
                     float(y + (line - kPad) / 2), kArrow);
  std::snprintf(label, sizeof label, "%.3g m/s", speed_scale);
  common::draw_text(img, x + 24 + 2 * kPad, y, label, scale, kInk);
  return img;
}

}  // namespace reach
