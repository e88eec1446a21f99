#pragma once
// A 5 x 7 pixel bitmap font for short labels on pictures (solver names, times): lowercase letters
// (capitals are drawn as lowercase), digits and ` .,-=:/()%_+?`; any other character is drawn
// as `?`. Glyphs advance 6 pixels (one of spacing), all multiplied by an integer scale.

#include <cstdint>
#include <string>

#include "common/image_writer.h"

namespace common {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

constexpr int kGlyphWidth = 5;
constexpr int kGlyphHeight = 7;
constexpr int kGlyphAdvance = 6;

// Width in pixels of `text` drawn at `scale` (no spacing after the last glyph).
int text_width(const std::string& text, int scale);

// Draws `text` with its top-left corner at (x, y); pixels outside the image are skipped.
void draw_text(RgbImage& image, int x, int y, const std::string& text, int scale, Rgb colour);

}  // namespace common
