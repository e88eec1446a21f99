#pragma once
// The river's centreline, a polyline in map coordinates from upstream to downstream: where along
// the river (km from its first point) and on which side (left or right bank, looking downstream)
// a point lies. Leading edges, arrivals and stranded oil per km are read on it.

#include <string>
#include <vector>

namespace farfield {

struct RiverPosition {
  double along_m = 0;   // distance along the centreline from its first point
  double offset_m = 0;  // signed distance from it: > 0 on the left bank's side
};

class Centreline {
 public:
  Centreline() = default;
  // At least two points, no two equal in a row; throws std::invalid_argument otherwise.
  explicit Centreline(std::vector<std::pair<double, double>> points);
  // The nearest point of the polyline; beyond its ends, along the end segments' extensions.
  RiverPosition locate(double x, double y) const;
  // The map point `along` metres down the centreline and `offset` metres to its left (< 0: right).
  void point_at(double along, double offset, double& x, double& y) const;
  double length() const { return cumulative_.empty() ? 0 : cumulative_.back(); }
  const std::vector<std::pair<double, double>>& points() const { return points_; }

 private:
  // The squared distance from (x, y) to segment k (the end segments extended beyond the line's
  // ends), and the projection's parameter s along it.
  double squared_distance(size_t k, double x, double y, double& s) const;
  // The nearest of `candidates` (ascending; null: every segment), the first of equals.
  RiverPosition nearest(const size_t* candidates, size_t count, double x, double y) const;
  void build_index();

  std::vector<std::pair<double, double>> points_;
  std::vector<double> cumulative_;  // distance to each point

  // A grid over the line's surroundings listing, per cell, the segments that can be the nearest
  // to some point of the cell, ascending: locate measures those instead of every segment.
  double grid_x0_ = 0, grid_y0_ = 0, grid_cell_ = 1;
  long grid_nx_ = 0, grid_ny_ = 0;
  std::vector<size_t> cell_start_;  // cell c's candidates: cell_segments_[start[c], start[c+1])
  std::vector<size_t> cell_segments_;
};

}  // namespace farfield
