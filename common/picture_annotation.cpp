#include "common/picture_annotation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/axis_ticks.h"
#include "common/bitmap_font.h"
#include "common/drawing.h"

namespace common {

namespace {

constexpr Rgb kInk{30, 30, 30};
constexpr Rgb kLeakColour{220, 30, 30};
constexpr Rgb kWatchColour{230, 120, 0};
constexpr int kPad = 8;

Rgb rgb(const Colour& c) {
  auto byte = [](float v) { return std::uint8_t(std::clamp(v, 0.f, 255.f)); };
  return {byte(c.r), byte(c.g), byte(c.b)};
}

// The leak's mark: a red cross in a white halo so it shows on water and oil alike.
void draw_leak_mark(RgbImage& img, float x, float y) {
  const float r = 7;
  draw_line(img, x - r, y - r, x + r, y + r, {255, 255, 255}, 6);
  draw_line(img, x - r, y + r, x + r, y - r, {255, 255, 255}, 6);
  draw_line(img, x - r, y - r, x + r, y + r, kLeakColour, 3);
  draw_line(img, x - r, y + r, x + r, y - r, kLeakColour, 3);
}

// A label on the picture: dark text on a white box, kept inside the image.
void draw_tag(RgbImage& img, int x, int y, const std::string& text, Rgb colour) {
  const int w = text_width(text, 1) + 4, h = kGlyphHeight + 4;
  x = std::clamp(x, 0, std::max(0, img.width - w));
  y = std::clamp(y, 0, std::max(0, img.height - h));
  fill_rect(img, x, y, w, h, {255, 255, 255});
  draw_text(img, x + 2, y + 2, text, 1, colour);
}

// Lays out legend entries left to right, wrapping to a new line when the band's width runs out.
class BandLayout {
 public:
  BandLayout(int width, int top) : width_(width), x_(kPad), y_(top) {}
  // Where an item `w` pixels wide goes; advances past it.
  std::pair<int, int> place(int w) {
    if (x_ > kPad && x_ + w > width_ - kPad) {
      x_ = kPad;
      y_ += line_height();
    }
    const std::pair<int, int> at{x_, y_};
    x_ += w + 3 * kPad;
    return at;
  }
  static int line_height() { return kGlyphHeight * kAnnotationTextScale + kPad + 4; }
  int bottom() const { return y_ + line_height(); }

 private:
  int width_, x_, y_;
};

constexpr int kSwatch = 14;

// The legend's entries, drawn into `img` when `draw` (else only laid out, to size the band).
int draw_legend(RgbImage& img, int top, ViewAxis axis, const PictureAnnotation& a, bool draw) {
  const int s = kAnnotationTextScale;
  BandLayout layout(img.width, top);
  auto text = [&](int x, int y, const std::string& t) {
    if (draw) draw_text(img, x, y + (kSwatch - kGlyphHeight * s) / 2, t, s, kInk);
  };
  auto swatch_entry = [&](const std::string& label, Rgb colour) {
    const auto [x, y] = layout.place(kSwatch + kPad + text_width(label, s));
    if (!draw) return;
    fill_rect(img, x, y, kSwatch, kSwatch, colour);
    text(x + kSwatch + kPad, y, label);
  };
  swatch_entry("water", rgb(fluid_colour(0, 0.6f)));
  {
    // Oil by its fraction: a ramp from water (0) to oil (1); 1/2 and more counts as oil.
    const std::string label = "oil fraction 0 - 1";
    const int ramp = 60;
    const auto [x, y] = layout.place(ramp + kPad + text_width(label, s));
    if (draw) {
      for (int k = 0; k < ramp; ++k)
        fill_rect(img, x + k, y, 1, kSwatch, rgb(fluid_colour(float(k) / float(ramp - 1), 0.6f)));
      fill_rect(img, x + ramp / 2, y + kSwatch - 4, 1, 4, {255, 255, 255});  // the 1/2 mark
      text(x + ramp + kPad, y, label);
    }
  }
  swatch_entry(a.river ? "terrain" : "walls", rgb(boundary_colour(axis, 0.5f)));
  if (!a.leaks.empty()) {
    const auto [x, y] = layout.place(kSwatch + kPad + text_width("leak", s));
    if (draw) {
      draw_leak_mark(img, float(x + kSwatch / 2), float(y + kSwatch / 2));
      text(x + kSwatch + kPad, y, "leak");
    }
  }
  if (!a.watch_points.empty() && axis != ViewAxis::kSide) {
    const auto [x, y] = layout.place(kSwatch + kPad + text_width("watch point", s));
    if (draw) {
      draw_circle(img, float(x + kSwatch / 2), float(y + kSwatch / 2), kSwatch / 2.f - 1,
                  kWatchColour, 2);
      text(x + kSwatch + kPad, y, "watch point");
    }
  }
  return layout.bottom();
}

}  // namespace

double scale_bar_length(double width_m) {
  const double target = width_m / 5;
  const double up = round_up_to_125(target);
  if (up <= target * (1 + 1e-9)) return up;
  // The next 1-2-5 value below: 5 -> 2, 2 -> 1, 1 -> 0.5.
  const double decade = std::pow(10.0, std::floor(std::log10(up) + 1e-9));
  const double mantissa = up / decade;
  return mantissa > 4 ? 2 * decade : mantissa > 1.5 ? decade : 0.5 * decade;
}

std::string time_label(double time_s) {
  char text[48];
  std::snprintf(text, sizeof text, "t = %.2f s", time_s);
  return text;
}

RgbImage annotate(const RgbImage& picture, const FrameRenderer& renderer, ViewAxis axis,
                  const PictureAnnotation& a) {
  RgbImage marked = picture;
  // Watch points (circles of their radius, with their names) and the leak, on the picture.
  if (axis != ViewAxis::kSide)
    for (const auto& w : a.watch_points) {
      const Eigen::Vector2f p = renderer.to_pixel(w.position, axis);
      const float r = std::max(4.f, w.radius_m * renderer.pixels_per_metre(axis));
      draw_circle(marked, p.x(), p.y(), r, kWatchColour, 2);
      draw_tag(marked, int(p.x() + r * 0.7f) + 2, int(p.y() - r * 0.7f) - kGlyphHeight - 4, w.label,
               kWatchColour);
    }
  for (const auto& l : a.leaks) {
    const Eigen::Vector2f p = renderer.to_pixel(l.position, axis);
    draw_leak_mark(marked, p.x(), p.y());
  }

  const int s = kAnnotationTextScale;
  const int first_line = picture.height + kPad;
  const int legend_top = first_line + BandLayout::line_height();
  RgbImage sizing;
  sizing.width = picture.width;
  const int band_bottom = draw_legend(sizing, legend_top, axis, a, false);
  RgbImage out;
  out.width = picture.width;
  out.height = band_bottom + kPad;
  out.pixels.assign(size_t(out.width) * size_t(out.height) * 3, 255);
  std::copy(marked.pixels.begin(), marked.pixels.end(), out.pixels.begin());
  fill_rect(out, 0, picture.height, out.width, 1, {160, 160, 160});  // the band's top edge

  // First line: time, flow direction, scale bar.
  const std::string time = time_label(a.time_s);
  draw_text(out, kPad, first_line, time, s, kInk);
  int x = kPad + text_width(time, s) + 4 * kPad;
  const int mid = first_line + kGlyphHeight * s / 2;
  if (a.river) {
    draw_text(out, x, first_line, "flow", s, kInk);
    x += text_width("flow", s) + kPad;
    if (axis == ViewAxis::kRiver)  // on the map the flow runs down the picture
      draw_arrow(out, float(x + 8), float(first_line - 2), float(x + 8), float(mid + 9), kInk);
    else
      draw_arrow(out, float(x), float(mid), float(x + 40), float(mid), kInk);
    x += 40 + 4 * kPad;
  }
  const float ppm = renderer.pixels_per_metre(axis);
  const double bar_m = scale_bar_length(double(picture.width) / double(ppm));
  const int bar_px = int(std::lround(bar_m * double(ppm)));
  const std::string bar_label = tick_label(bar_m, bar_m) + " m";
  const int bar_x = std::max(x, out.width - kPad - bar_px - kPad - text_width(bar_label, s));
  fill_rect(out, bar_x, mid - 2, bar_px, 4, kInk);
  fill_rect(out, bar_x, mid - 7, 2, 14, kInk);
  fill_rect(out, bar_x + bar_px - 2, mid - 7, 2, 14, kInk);
  draw_text(out, bar_x + bar_px + kPad, first_line, bar_label, s, kInk);

  draw_legend(out, legend_top, axis, a, true);
  return out;
}

}  // namespace common
