#include "common/drawing.h"

#include <algorithm>
#include <cmath>

namespace common {

void put(RgbImage& img, int x, int y, Rgb c) {
  if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
  std::uint8_t* p = &img.pixels[(size_t(y) * size_t(img.width) + size_t(x)) * 3];
  p[0] = c.r, p[1] = c.g, p[2] = c.b;
}

void fill_rect(RgbImage& img, int x0, int y0, int w, int h, Rgb c) {
  for (int y = y0; y < y0 + h; ++y)
    for (int x = x0; x < x0 + w; ++x) put(img, x, y, c);
}

void draw_line(RgbImage& img, float x0, float y0, float x1, float y1, Rgb c, int thickness) {
  const int steps = std::max(1, int(std::ceil(std::max(std::abs(x1 - x0), std::abs(y1 - y0)))));
  const int half = thickness / 2;
  for (int k = 0; k <= steps; ++k) {
    const float t = float(k) / float(steps);
    const int x = int(std::lround(x0 + t * (x1 - x0))), y = int(std::lround(y0 + t * (y1 - y0)));
    fill_rect(img, x - half, y - half, thickness, thickness, c);
  }
}

void draw_circle(RgbImage& img, float cx, float cy, float radius, Rgb c, int thickness) {
  const int segments = std::max(24, int(radius));
  for (int k = 0; k < segments; ++k) {
    const float a0 = 6.2831853f * float(k) / float(segments);
    const float a1 = 6.2831853f * float(k + 1) / float(segments);
    draw_line(img, cx + radius * std::cos(a0), cy + radius * std::sin(a0),
              cx + radius * std::cos(a1), cy + radius * std::sin(a1), c, thickness);
  }
}

void draw_arrow(RgbImage& img, float x0, float y0, float x1, float y1, Rgb c) {
  draw_line(img, x0, y0, x1, y1, c, 3);
  const float len = std::hypot(x1 - x0, y1 - y0), head = 9;
  const float ux = (x1 - x0) / len, uy = (y1 - y0) / len;
  draw_line(img, x1, y1, x1 - head * (ux - 0.6f * uy), y1 - head * (uy + 0.6f * ux), c, 3);
  draw_line(img, x1, y1, x1 - head * (ux + 0.6f * uy), y1 - head * (uy - 0.6f * ux), c, 3);
}

}  // namespace common
