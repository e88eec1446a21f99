#pragma once
// What makes a frame's picture readable on its own, pasted into a report: a band under the
// picture with the simulated time, a scale bar of a round length in metres, the flow direction
// and a legend (water, oil by its fraction, terrain or walls, leak, watch point), and on the
// picture itself the leak and the watch points where the scene has them.

#include <string>
#include <vector>

#include "common/image_writer.h"

namespace common {

struct PictureMarker {
  Point position = Point::Zero();
  std::string label;
  float radius_m = 0;  // a watch point's radius, drawn as a circle; 0 for the leak's mark
};

struct PictureAnnotation {
  double time_s = 0;
  bool river = false;  // the flow runs along +x and the boundary is terrain
  std::vector<PictureMarker> leaks;
  std::vector<PictureMarker> watch_points;  // drawn on the views from above only
};

// Text scale (the bitmap font's pixels per font pixel) of the band.
constexpr int kAnnotationTextScale = 2;

// `picture` (made by `renderer` in `axis`'s view) with the markers drawn on it and the band
// appended below it; the width is unchanged.
RgbImage annotate(const RgbImage& picture, const FrameRenderer& renderer, ViewAxis axis,
                  const PictureAnnotation& annotation);

// The length of the scale bar for a picture `width_m` metres wide: the 1-2-5 round length
// nearest below a fifth of the width.
double scale_bar_length(double width_m);

// "t = 4.20 s": the time with two decimals (frames are at least 0.01 s apart in our scenes).
std::string time_label(double time_s);

}  // namespace common
