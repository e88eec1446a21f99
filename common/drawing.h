#pragma once
// Pen strokes on an RgbImage: pixels, filled rectangles, lines, circles and arrows, clipped to
// the image. Shared by the frame annotations and the reach's maps.

#include "common/bitmap_font.h"
#include "common/image_writer.h"

namespace common {

void put(RgbImage& img, int x, int y, Rgb c);
void fill_rect(RgbImage& img, int x0, int y0, int w, int h, Rgb c);
// A line `thickness` pixels wide (square pen), by stepping along its longer axis.
void draw_line(RgbImage& img, float x0, float y0, float x1, float y1, Rgb c, int thickness);
void draw_circle(RgbImage& img, float cx, float cy, float radius, Rgb c, int thickness);
// An arrow from (x0, y0) to its head at (x1, y1), 3 pixels wide with a 9-pixel head.
void draw_arrow(RgbImage& img, float x0, float y0, float x1, float y1, Rgb c);

}  // namespace common
