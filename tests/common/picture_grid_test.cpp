// The labelled picture grid of comparison figures and its bitmap font: the layout the header
// promises, pictures copied to their cells, misuse refused naming the sizes.

#include "common/picture_grid.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace common {
namespace {

RgbImage filled(int width, int height, std::uint8_t value) {
  RgbImage img;
  img.width = width;
  img.height = height;
  img.pixels.assign(size_t(width) * size_t(height) * 3, value);
  return img;
}

const std::uint8_t* pixel(const RgbImage& img, int x, int y) {
  return &img.pixels[(size_t(y) * size_t(img.width) + size_t(x)) * 3];
}

TEST(BitmapFont, WidthIsGlyphsTimesAdvanceLessTheLastSpace) {
  EXPECT_EQ(text_width("", 2), 0);
  EXPECT_EQ(text_width("a", 1), 5);
  EXPECT_EQ(text_width("dfsph", 1), 29);
  EXPECT_EQ(text_width("dfsph", 2), 58);
  // Ink stays inside that width and the glyph height, and off-image pixels are skipped.
  RgbImage img = filled(40, 20, 255);
  draw_text(img, 1, 1, "t = 0.5 s", 1, Rgb{0, 0, 0});
  draw_text(img, 30, 15, "wxyz", 2, Rgb{0, 0, 0});
  long ink = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (pixel(img, x, y)[0] == 0 && y < 10) {  // the first text's ink
        ++ink;
        EXPECT_GE(x, 1);
        EXPECT_LT(x, 1 + text_width("t = 0.5 s", 1)) << x << ", " << y;
        EXPECT_LT(y, 1 + kGlyphHeight) << x << ", " << y;
      }
  EXPECT_GT(ink, 20);
}

TEST(PictureGrid, LayoutAndCells) {
  PictureGrid grid(30, 20, {"a", "b", "c"}, {"t = 1 s", "t = 2 s"});
  const int g = PictureGrid::kGap;
  EXPECT_EQ(grid.label_width(), text_width("t = 1 s", PictureGrid::kTextScale) + 2 * g);
  EXPECT_EQ(grid.label_height(), kGlyphHeight * PictureGrid::kTextScale + 2 * g);
  EXPECT_EQ(grid.image().width, grid.label_width() + 3 * (30 + g) + g);
  EXPECT_EQ(grid.image().height, grid.label_height() + 2 * (20 + g) + g);
  EXPECT_EQ(grid.cell_x(1) - grid.cell_x(0), 30 + g);
  EXPECT_EQ(grid.cell_y(1) - grid.cell_y(0), 20 + g);

  grid.place(1, 2, filled(30, 20, 7));
  grid.leave_empty(0, 1, "x");
  const RgbImage& img = grid.image();
  // The placed picture fills its cell exactly; the gap beside it stays white.
  EXPECT_EQ(pixel(img, grid.cell_x(2), grid.cell_y(1))[0], 7);
  EXPECT_EQ(pixel(img, grid.cell_x(2) + 29, grid.cell_y(1) + 19)[2], 7);
  EXPECT_EQ(pixel(img, grid.cell_x(2) - 1, grid.cell_y(1))[0], 255);
  EXPECT_EQ(pixel(img, grid.cell_x(2), grid.cell_y(1) + 20)[0], 255);
  EXPECT_EQ(pixel(img, grid.cell_x(1), grid.cell_y(0))[0], PictureGrid::kEmpty.r);
  // An untouched cell is white.
  EXPECT_EQ(pixel(img, grid.cell_x(0) + 15, grid.cell_y(0) + 10)[0], 255);

  try {
    grid.place(0, 0, filled(31, 20, 0));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("expected a 30 x 20 picture, got 31 x 20"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(grid.place(2, 0, filled(30, 20, 0)), std::out_of_range);
  EXPECT_THROW(grid.leave_empty(0, 3, ""), std::out_of_range);
  EXPECT_THROW(PictureGrid(0, 20, {"a"}, {"b"}), std::invalid_argument);
  EXPECT_THROW(PictureGrid(10, 20, {}, {"b"}), std::invalid_argument);
}

}  // namespace
}  // namespace common
