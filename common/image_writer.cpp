#include "common/image_writer.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <numeric>
#include <stdexcept>

namespace common {

namespace {

// Axes of the picture: horizontal, vertical, and depth (toward the viewer is larger).
void view_axes(ViewAxis axis, int& h, int& v, int& d) {
  h = 0;
  if (axis == ViewAxis::kRiver) {
    h = 1;  // y to the right
    v = 0;  // x downward (see draw_points)
    d = 2;  // looking down: larger z is nearer
  } else if (axis == ViewAxis::kSide) {
    v = 2;
    d = 1;  // looking along +y: smaller y is nearer... we treat smaller y as nearer
  } else {
    v = 1;
    d = 2;  // looking down: larger z is nearer
  }
}

void draw_disc(RgbImage& img, float cx, float cy, float radius, const Colour& c) {
  const int x0 = std::max(0, int(std::floor(cx - radius))),
            x1 = std::min(img.width - 1, int(std::ceil(cx + radius)));
  const int y0 = std::max(0, int(std::floor(cy - radius))),
            y1 = std::min(img.height - 1, int(std::ceil(cy + radius)));
  const float r2 = radius * radius;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const float dx = float(x) + 0.5f - cx, dy = float(y) + 0.5f - cy;
      if (dx * dx + dy * dy > r2) continue;
      std::uint8_t* p = &img.pixels[size_t(3 * (y * img.width + x))];
      p[0] = std::uint8_t(std::clamp(c.r, 0.f, 255.f));
      p[1] = std::uint8_t(std::clamp(c.g, 0.f, 255.f));
      p[2] = std::uint8_t(std::clamp(c.b, 0.f, 255.f));
    }
}

// Draws points far-to-near as shaded discs.
template <class ColourOf>
void draw_points(RgbImage& img, const Bounds& bounds, float particle_radius, ViewAxis axis,
                 const std::vector<Point>& points, ColourOf colour_of) {
  int ah, av, ad;
  view_axes(axis, ah, av, ad);
  const Point size = bounds.max - bounds.min;
  const float scale = float(img.width) / float(size[ah]);
  const float radius = std::max(1.0f, float(particle_radius) * scale * 1.2f);
  const bool near_is_small = axis == ViewAxis::kSide;
  auto nearness = [&](const Point& p) {
    const float t = float((p[ad] - bounds.min[ad]) / size[ad]);
    return std::clamp(near_is_small ? 1 - t : t, 0.f, 1.f);
  };
  std::vector<size_t> order(points.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return nearness(points[a]) < nearness(points[b]); });
  for (size_t i : order) {
    const float x = float(points[i][ah] - bounds.min[ah]) * scale;
    const float along = float(points[i][av] - bounds.min[av]) * scale;
    const float y = axis == ViewAxis::kRiver ? along : float(img.height) - along;
    draw_disc(img, x, y, radius, colour_of(i, nearness(points[i])));
  }
}

}  // namespace

FrameRenderer::FrameRenderer(const std::vector<Point>& boundary, const Bounds& bounds,
                             float particle_radius, int width)
    : bounds_(bounds), particle_radius_(particle_radius), width_(width) {
  for (ViewAxis axis : {ViewAxis::kSide, ViewAxis::kTop, ViewAxis::kRiver}) {
    RgbImage& img = background_[int(axis)];
    img = blank(axis);
    draw_points(img, bounds_, particle_radius_, axis, boundary,
                [axis](size_t, float n) { return boundary_colour(axis, n); });
  }
}

RgbImage FrameRenderer::blank(ViewAxis axis) const {
  int ah, av, ad;
  view_axes(axis, ah, av, ad);
  const Point size = bounds_.max - bounds_.min;
  RgbImage img;
  img.width = width_;
  img.height = std::max(1, int(std::lround(float(size[av]) * float(width_) / float(size[ah]))));
  img.pixels.assign(size_t(img.width * img.height * 3), 255);
  return img;
}

Colour fluid_colour(float oil_fraction, float n) {
  const float f = std::clamp(oil_fraction, 0.f, 1.f);
  const Colour water{20 + 60 * n, 70 + 90 * n, 150 + 100 * n};
  const Colour oil{20 + 50 * n, 18 + 40 * n, 15 + 30 * n};
  return {water.r + f * (oil.r - water.r), water.g + f * (oil.g - water.g),
          water.b + f * (oil.b - water.b)};
}

Colour boundary_colour(ViewAxis axis, float n) {
  // Terrain seen from above in earth tones, lighter where higher; walls grey.
  if (axis == ViewAxis::kRiver) return Colour{120 + 100 * n, 105 + 85 * n, 70 + 60 * n};
  const float g = 150 + 60 * n;
  return Colour{g, g, g};
}

RgbImage FrameRenderer::render(const std::vector<Point>& fluid,
                               const std::vector<std::uint8_t>& oil, ViewAxis axis) const {
  std::vector<float> fraction(oil.size());
  for (size_t i = 0; i < oil.size(); ++i) fraction[i] = oil[i] ? 1.f : 0.f;
  return render(fluid, fraction, axis);
}

RgbImage FrameRenderer::render(const std::vector<Point>& fluid,
                               const std::vector<float>& oil_fraction, ViewAxis axis) const {
  RgbImage img = background_[int(axis)];
  draw_points(img, bounds_, particle_radius_, axis, fluid,
              [&](size_t i, float n) { return fluid_colour(oil_fraction[i], n); });
  return img;
}

float FrameRenderer::pixels_per_metre(ViewAxis axis) const {
  int ah, av, ad;
  view_axes(axis, ah, av, ad);
  return float(width_) / float(bounds_.max[ah] - bounds_.min[ah]);
}

Eigen::Vector2f FrameRenderer::to_pixel(const Point& p, ViewAxis axis) const {
  // The same projection as draw_points.
  int ah, av, ad;
  view_axes(axis, ah, av, ad);
  const float scale = pixels_per_metre(axis);
  const float x = (p[ah] - bounds_.min[ah]) * scale;
  const float along = (p[av] - bounds_.min[av]) * scale;
  if (axis == ViewAxis::kRiver) return {x, along};
  const int height =
      std::max(1, int(std::lround((bounds_.max[av] - bounds_.min[av]) * float(width_) /
                                  (bounds_.max[ah] - bounds_.min[ah]))));
  return {x, float(height) - along};
}

void write_png(const std::string& file, const RgbImage& image) {
  // libpng with zlib's fastest level and no row filters: a frame's picture costs a few
  // milliseconds (stb_image_write's own deflate took ~60 ms per 800 x 600 picture).
  FILE* out = std::fopen(file.c_str(), "wb");
  if (!out) throw std::runtime_error(file + ": cannot open for writing");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(out);
    throw std::runtime_error(file + ": cannot write PNG");
  }
  png_init_io(png, out);
  png_set_compression_level(png, 1);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
  png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y)
    png_write_row(png, image.pixels.data() + size_t(3 * y * image.width));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fclose(out) != 0) throw std::runtime_error(file + ": write failed");
}

}  // namespace common
