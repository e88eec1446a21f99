#pragma once
// What a responder reads off the far field at one moment: the oiled area of the water, the
// leading edge along the river (km), the oiled length and stranded volume of each bank per km,
// the budget, and what has reached each watch point.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "farfield/model/far_field_model.h"
#include "reach/grid.h"

namespace farfield {

struct WatchPoint {
  std::string name;
  double x = 0, y = 0, radius = 50;
  double km = 0;          // along the centreline
  double arrival_s = -1;  // first time oil came within the radius; < 0: not yet
};

// The cell of `grid` holding map point (x, y) (its index), or false outside the grid.
bool cell_holding(const reach::Grid& grid, double x, double y, size_t& cell);

// The floating oil's footprint on `grid`: each element's area spread over the cell it lies in,
// a cell covered at most once (m^2 per cell).
reach::Field oiled_cells(const FarFieldModel& model, const reach::Grid& grid);

// The floating oil's emulsion volume in each cell of `grid` (m^3): with oiled_cells, the film's
// thickness there.
reach::Field oiled_volume(const FarFieldModel& model, const reach::Grid& grid);

// Marks each watch point's arrival when any floating or stranded element lies within its radius
// (called after every step).
void update_arrivals(const FarFieldModel& model, std::vector<WatchPoint>& points);

// The record of one output time (forecast.json's "outputs" entries).
nlohmann::json forecast_record(const FarFieldModel& model, const reach::Grid& grid,
                               const std::vector<WatchPoint>& points);

}  // namespace farfield
