#include "farfield/outputs/forecast_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/bitmap_font.h"
#include "common/drawing.h"
#include "common/picture_annotation.h"
#include "farfield/outputs/appearance.h"
#include "reach/reach_map.h"

namespace farfield {

namespace {
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
// The watch points as named magenta triangles.
void draw_watch_points(common::RgbImage& img, const reach::MapFrame& frame,
                       const std::vector<WatchPoint>& points) {
  for (const WatchPoint& p : points) {
    double px, py;
    frame.to_pixel(p.x, p.y, px, py);
    triangle(img, px, py, 12, kWatch);
    if (py < frame.height - 10)
      common::draw_text(img, int(px) + 9, int(py) - 6, p.name, common::kAnnotationTextScale,
                        kWatch);
  }
}
}  // namespace

void map_colour_scales(const ReachFlow& flow, double& depth_scale, double& speed_scale) {
  depth_scale = speed_scale = 0.5;
  const reach::WaterState w = flow.water_at(0);
  for (size_t c = 0; c < w.h.size(); ++c)
    if (w.h[c] > 0.01) {
      depth_scale = std::max(depth_scale, w.h[c]);
      speed_scale = std::max(speed_scale, std::hypot(w.hu[c], w.hv[c]) / w.h[c]);
    }
}

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
            state == ElementState::floating ? bonn_class(model.thickness(e)).colour : kStranded);
    }
  draw_watch_points(img, frame, points);
  const int scale = common::kAnnotationTextScale;

  // The band's third line: the legend and the budget.
  const int pad = 8, line = common::kGlyphHeight * scale + pad;
  const int y = frame.band_top + pad + 2 * (line + pad / 2);
  int x = pad;
  // Afloat by the film's Bonn Agreement appearance code, 1 (sheen) to 5 (continuous true colour),
  // each dot labelled by its code.
  for (const AppearanceClass& c : bonn_classes()) {
    dot(img, x + 4, y + (line - pad) / 2, 3, c.colour);
    x += 10;
    const std::string code = std::to_string(c.code);
    common::draw_text(img, x, y, code, scale, kInk);
    x += common::text_width(code, scale) + 4;
  }
  x += pad;
  dot(img, x + 4, y + (line - pad) / 2, 3, kStranded);
  x += 14;
  common::draw_text(img, x, y, "stranded", scale, kInk);
  x += common::text_width("stranded", scale) + pad;
  triangle(img, x + 5, y + (line - pad) / 2, 10, kWatch);
  x += 14;
  common::draw_text(img, x, y, "watch", scale, kInk);
  x += common::text_width("watch", scale) + pad;
  const Budget b = model.budget();
  if (b.released > 0) {
    char text[160];
    std::snprintf(text, sizeof text, "%.0f%% afloat %.0f%% banks %.0f%% air %.0f%% out",
                  100 * b.floating / b.released, 100 * b.stranded / b.released,
                  100 * b.evaporated / b.released,
                  100 * (b.dispersed + b.left_reach + b.sunk) / b.released);
    common::draw_text(img, x, y, text, scale, kInk);
  }
  return img;
}

namespace {
// The probability classes: lower bounds and colours.
constexpr double kClassFloor[] = {0.0, 0.1, 0.3, 0.6, 0.9};
constexpr common::Rgb kClassColour[] = {
    {255, 237, 160}, {254, 178, 76}, {253, 110, 40}, {220, 30, 30}, {128, 0, 38}};
constexpr const char* kClassLabel[] = {"0-10", "10-30", "30-60", "60-90", "90-100%"};

int probability_class(double p) {
  int k = 0;
  while (k + 1 < 5 && p >= kClassFloor[k + 1]) ++k;
  return k;
}
}  // namespace

common::RgbImage draw_probability_map(const ReachFlow& flow, const reach::Field& probability,
                                      double t, int members, const std::vector<WatchPoint>& points,
                                      double depth_scale, double speed_scale, int max_width) {
  const reach::Grid& g = flow.grid();
  common::RgbImage img = reach::draw_reach_map(g, flow.bed(), flow.water_at(t), t, depth_scale,
                                               speed_scale, 0.01, max_width);
  const reach::MapFrame frame = reach::reach_map_frame(g, max_width);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double p = probability[g.at(i, j)];
      if (!(p > 0)) continue;
      double left, top, right, bottom;
      frame.to_pixel(g.x0 + i * g.dx, g.y0 + (j + 1) * g.dy, left, top);
      frame.to_pixel(g.x0 + (i + 1) * g.dx, g.y0 + j * g.dy, right, bottom);
      const int x0 = int(std::floor(left)), y0 = int(std::floor(top));
      const int w = std::max(1, int(std::ceil(right)) - x0),
                h = std::max(1, int(std::ceil(bottom)) - y0);
      common::fill_rect(img, x0, y0, w, std::min(h, frame.height - y0),
                        kClassColour[probability_class(p)]);
    }
  draw_watch_points(img, frame, points);
  const int scale = common::kAnnotationTextScale;
  const int pad = 8, line = common::kGlyphHeight * scale + pad;
  const int y = frame.band_top + pad + 2 * (line + pad / 2);
  int x = pad;
  const std::string title = "oiled by now (" + std::to_string(members) + " members):";
  common::draw_text(img, x, y, title, scale, kInk);
  x += common::text_width(title, scale) + pad;
  for (int k = 0; k < 5; ++k) {
    common::fill_rect(img, x, y, 12, line - pad, kClassColour[k]);
    x += 16;
    common::draw_text(img, x, y, kClassLabel[k], scale, kInk);
    x += common::text_width(kClassLabel[k], scale) + pad;
  }
  return img;
}

}  // namespace farfield
