#include "farfield/outputs/forecast_map.h"

#include <cmath>
#include <cstdio>

#include "common/bitmap_font.h"
#include "common/drawing.h"
#include "common/picture_annotation.h"
#include "reach/reach_map.h"

namespace farfield {

namespace {
constexpr common::Rgb kFloating{60, 35, 10};
constexpr common::Rgb kStranded{220, 40, 30};
constexpr common::Rgb kWatch{200, 0, 200};
constexpr common::Rgb kInk{30, 30, 30};

void dot(common::RgbImage& img, double px, double py, int radius, common::Rgb c) {
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx)
      if (dx * dx + dy * dy <= radius * radius + radius)
        common::put(img, int(std::lround(px)) + dx, int(std::lround(py)) + dy, c);
}

void triangle(common::RgbImage& img, double px, double py, int size, common::Rgb c) {
  for (int row = 0; row <= size; ++row) {
    const int half = row / 2;
    common::fill_rect(img, int(std::lround(px)) - half, int(std::lround(py)) - size / 2 + row,
                      2 * half + 1, 1, c);
  }
}
}  // namespace

common::RgbImage draw_forecast_map(const ReachFlow& flow, const FarFieldModel& model,
                                   const std::vector<WatchPoint>& points, double depth_scale,
                                   double speed_scale, int max_width) {
  const double t = model.time();
  common::RgbImage img = reach::draw_reach_map(flow.grid(), flow.bed(), flow.water_at(t), t,
                                               depth_scale, speed_scale, 0.01, max_width);
  const reach::MapFrame frame = reach::reach_map_frame(flow.grid(), max_width);
  const Elements& el = model.elements();
  for (const ElementState state : {ElementState::stranded, ElementState::floating})
    for (size_t e = 0; e < el.size(); ++e) {
      if (el.state[e] != state) continue;
      double px, py;
      frame.to_pixel(el.x[e], el.y[e], px, py);
      if (py < frame.height)
        dot(img, px, py, state == ElementState::floating ? 1 : 2,
            state == ElementState::floating ? kFloating : kStranded);
    }
  const int scale = common::kAnnotationTextScale;
  for (const WatchPoint& p : points) {
    double px, py;
    frame.to_pixel(p.x, p.y, px, py);
    triangle(img, px, py, 12, kWatch);
    if (py < frame.height - 10)
      common::draw_text(img, int(px) + 9, int(py) - 6, p.name, scale, kWatch);
  }

  // The band's third line: the legend and the budget.
  const int pad = 8, line = common::kGlyphHeight * scale + pad;
  const int y = frame.band_top + pad + 2 * (line + pad / 2);
  int x = pad;
  dot(img, x + 4, y + (line - pad) / 2, 3, kFloating);
  x += 14;
  common::draw_text(img, x, y, "afloat", scale, kInk);
  x += common::text_width("afloat", scale) + 2 * pad;
  dot(img, x + 4, y + (line - pad) / 2, 3, kStranded);
  x += 14;
  common::draw_text(img, x, y, "on banks", scale, kInk);
  x += common::text_width("on banks", scale) + 2 * pad;
  triangle(img, x + 5, y + (line - pad) / 2, 10, kWatch);
  x += 14;
  common::draw_text(img, x, y, "watch", scale, kInk);
  x += common::text_width("watch", scale) + 3 * pad;
  const Budget b = model.budget();
  if (b.released > 0) {
    char text[160];
    std::snprintf(text, sizeof text, "%.0f%% afloat %.0f%% banks %.0f%% air %.0f%% out",
                  100 * b.floating / b.released, 100 * b.stranded / b.released,
                  100 * b.evaporated / b.released, 100 * (b.dispersed + b.left_reach) / b.released);
    common::draw_text(img, x, y, text, scale, kInk);
  }
  return img;
}

}  // namespace farfield
