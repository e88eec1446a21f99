#pragma once
// Pictures of one size in a grid with a label above each column and left of each row: the
// layout of a paper's comparison figure (one column per method, one row per moment).
//
// Layout, in pixels: kGap of white around and between the cells; above the cells a band as high
// as a line of text at kTextScale plus 2 kGap; left of them a band as wide as the widest row
// label plus 2 kGap. So the picture is
//   width  = label_width  + columns * (cell_width  + kGap) + kGap
//   height = label_height + rows    * (cell_height + kGap) + kGap
// with cell (row, column) at (cell_x(column), cell_y(row)).

#include <string>
#include <vector>

#include "common/bitmap_font.h"
#include "common/image_writer.h"

namespace common {

class PictureGrid {
 public:
  static constexpr int kGap = 4;
  static constexpr int kTextScale = 2;
  // Grey of a cell left empty (leave_empty).
  static constexpr Rgb kEmpty{200, 200, 200};

  // Throws std::invalid_argument for a cell smaller than 1 x 1 or no rows or columns.
  PictureGrid(int cell_width, int cell_height, const std::vector<std::string>& column_labels,
              const std::vector<std::string>& row_labels);

  int cell_width() const { return cell_width_; }
  int cell_height() const { return cell_height_; }
  int label_width() const { return label_width_; }
  int label_height() const { return label_height_; }
  int cell_x(int column) const { return label_width_ + kGap + column * (cell_width_ + kGap); }
  int cell_y(int row) const { return label_height_ + kGap + row * (cell_height_ + kGap); }

  // Copies `picture` into cell (row, column). Throws std::invalid_argument naming both sizes when
  // the picture is not cell_width x cell_height, std::out_of_range for a cell outside the grid.
  void place(int row, int column, const RgbImage& picture);
  // Fills cell (row, column) with kEmpty and writes `note` across its middle (a picture that
  // could not be made).
  void leave_empty(int row, int column, const std::string& note);

  const RgbImage& image() const { return image_; }

 private:
  void check_cell(int row, int column) const;
  int cell_width_, cell_height_, columns_, rows_;
  int label_width_ = 0, label_height_ = 0;
  RgbImage image_;
};

}  // namespace common
