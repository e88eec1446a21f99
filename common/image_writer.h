#pragma once
// Orthographic pictures of a frame (PNG via libpng): a side view (x right, z up), a
// top view (x right, y up) and, for rivers, a map view from above with the flow (+x) running
// down the picture and so the left bank (+y) on the right, as river maps are drawn. Boundary
// particles are drawn grey behind the fluid (terrain in earth tones on the map); fluid is blue
// for water and near-black for oil, mixtures in between by their oil fraction, each shaded
// lighter toward the viewer so depth stays readable.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace common {

// Pictures are drawn in single precision whatever the simulator's precision.
using Point = Eigen::Vector3f;
struct Bounds {
  Point min = Point::Zero();
  Point max = Point::Zero();
};

enum class ViewAxis { kSide, kTop, kRiver };

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // [height, width, 3], row 0 at the top
};

struct Colour {
  float r, g, b;  // 0-255
};

// A fluid particle's colour: water blue to oil near-black by its oil fraction (0-1); `nearness`
// (0 far, 1 near the viewer) lightens it. The pictures and their legends share it.
Colour fluid_colour(float oil_fraction, float nearness);
// The boundary's colour in `axis`'s view at `nearness` (terrain on the river map, grey walls).
Colour boundary_colour(ViewAxis axis, float nearness);

// Draws frames of one scene; the static boundary is drawn once per view and reused as the
// background of every frame.
class FrameRenderer {
 public:
  FrameRenderer(const std::vector<Point>& boundary, const Bounds& bounds, float particle_radius,
                int width = 800);
  // `oil` says, per fluid point, whether it is drawn as oil (else as water).
  RgbImage render(const std::vector<Point>& fluid, const std::vector<std::uint8_t>& oil,
                  ViewAxis axis) const;
  // Each fluid point coloured by its oil fraction (0-1).
  RgbImage render(const std::vector<Point>& fluid, const std::vector<float>& oil_fraction,
                  ViewAxis axis) const;

  // Where a point of the scene lands in `axis`'s picture (pixels from the top-left corner).
  Eigen::Vector2f to_pixel(const Point& p, ViewAxis axis) const;
  float pixels_per_metre(ViewAxis axis) const;

 private:
  RgbImage blank(ViewAxis axis) const;
  Bounds bounds_;
  float particle_radius_;
  int width_;
  RgbImage background_[3];
};

// Throws std::runtime_error naming the file when it cannot be written.
void write_png(const std::string& file, const RgbImage& image);

}  // namespace common
