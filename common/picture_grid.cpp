#include "common/picture_grid.h"

#include <algorithm>
#include <stdexcept>

namespace common {

namespace {

constexpr Rgb kInk{0, 0, 0};

// The largest scale up to PictureGrid::kTextScale at which `text` fits in `width` pixels, and the
// text cut to fit at scale 1 if it does not fit even then.
std::pair<std::string, int> fitted(std::string text, int width) {
  for (int scale = PictureGrid::kTextScale; scale >= 1; --scale)
    if (text_width(text, scale) <= width) return {text, scale};
  while (!text.empty() && text_width(text, 1) > width) text.pop_back();
  return {text, 1};
}

}  // namespace

PictureGrid::PictureGrid(int cell_width, int cell_height,
                         const std::vector<std::string>& column_labels,
                         const std::vector<std::string>& row_labels)
    : cell_width_(cell_width),
      cell_height_(cell_height),
      columns_(int(column_labels.size())),
      rows_(int(row_labels.size())) {
  if (cell_width < 1 || cell_height < 1 || columns_ < 1 || rows_ < 1)
    throw std::invalid_argument(
        "picture grid: expected cells of at least 1 x 1 pixel and at "
        "least one row and one column, got " +
        std::to_string(rows_) + " x " + std::to_string(columns_) + " cells of " +
        std::to_string(cell_width) + " x " + std::to_string(cell_height));
  for (const auto& label : row_labels)
    label_width_ = std::max(label_width_, text_width(label, kTextScale));
  label_width_ += 2 * kGap;
  label_height_ = kGlyphHeight * kTextScale + 2 * kGap;
  image_.width = label_width_ + columns_ * (cell_width_ + kGap) + kGap;
  image_.height = label_height_ + rows_ * (cell_height_ + kGap) + kGap;
  image_.pixels.assign(size_t(image_.width) * size_t(image_.height) * 3, 255);
  for (int c = 0; c < columns_; ++c) {
    const auto [text, scale] = fitted(column_labels[size_t(c)], cell_width_);
    draw_text(image_, cell_x(c) + (cell_width_ - text_width(text, scale)) / 2,
              kGap + (kGlyphHeight * kTextScale - kGlyphHeight * scale) / 2, text, scale, kInk);
  }
  for (int r = 0; r < rows_; ++r)
    draw_text(image_, kGap, cell_y(r) + (cell_height_ - kGlyphHeight * kTextScale) / 2,
              row_labels[size_t(r)], kTextScale, kInk);
}

void PictureGrid::check_cell(int row, int column) const {
  if (row < 0 || row >= rows_ || column < 0 || column >= columns_)
    throw std::out_of_range("picture grid: cell (" + std::to_string(row) + ", " +
                            std::to_string(column) + ") outside " + std::to_string(rows_) + " x " +
                            std::to_string(columns_));
}

void PictureGrid::place(int row, int column, const RgbImage& picture) {
  check_cell(row, column);
  if (picture.width != cell_width_ || picture.height != cell_height_)
    throw std::invalid_argument("picture grid: expected a " + std::to_string(cell_width_) + " x " +
                                std::to_string(cell_height_) + " picture, got " +
                                std::to_string(picture.width) + " x " +
                                std::to_string(picture.height));
  const size_t row_bytes = size_t(cell_width_) * 3;
  for (int y = 0; y < cell_height_; ++y)
    std::copy_n(
        &picture.pixels[size_t(y) * row_bytes], row_bytes,
        &image_.pixels[(size_t(cell_y(row) + y) * size_t(image_.width) + size_t(cell_x(column))) *
                       3]);
}

void PictureGrid::leave_empty(int row, int column, const std::string& note) {
  check_cell(row, column);
  for (int y = 0; y < cell_height_; ++y)
    for (int x = 0; x < cell_width_; ++x) {
      std::uint8_t* p = &image_.pixels[(size_t(cell_y(row) + y) * size_t(image_.width) +
                                        size_t(cell_x(column) + x)) *
                                       3];
      p[0] = kEmpty.r;
      p[1] = kEmpty.g;
      p[2] = kEmpty.b;
    }
  const auto [text, scale] = fitted(note, cell_width_);
  draw_text(image_, cell_x(column) + (cell_width_ - text_width(text, scale)) / 2,
            cell_y(row) + (cell_height_ - kGlyphHeight * scale) / 2, text, scale, kInk);
}

}  // namespace common
