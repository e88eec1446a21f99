#pragma once
// Orthographic pictures of a frame (PNG via libpng): a side view (x right, z up), a
// top view (x right, y up) and, for rivers, a map view from above with the flow (+x) running
// down the picture and so the left bank (+y) on the right, as river maps are drawn. Boundary
// particles are drawn grey behind the fluid; water is blue, oil near-black, each shaded lighter
// toward the viewer so depth stays readable.

#include <cstdint>
#include <string>
#include <vector>

#include "sph/types.h"

namespace sph {

enum class ViewAxis { kSide, kTop, kRiver };

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // [height, width, 3], row 0 at the top
};

// Draws frames of one scene; the static boundary is drawn once per view and reused as the
// background of every frame.
class FrameRenderer {
 public:
  FrameRenderer(const std::vector<Vec3>& boundary, const Aabb& bounds, Real particle_radius,
                int width = 800);
  // `fluid_type` holds ParticleType codes, one per fluid position.
  RgbImage render(const std::vector<Vec3>& fluid, const std::vector<std::int32_t>& fluid_type,
                  ViewAxis axis) const;

 private:
  RgbImage blank(ViewAxis axis) const;
  Aabb bounds_;
  Real particle_radius_;
  int width_;
  RgbImage background_[3];
};

// Throws SimulationError naming the file when it cannot be written.
void write_png(const std::string& file, const RgbImage& image);

}  // namespace sph
