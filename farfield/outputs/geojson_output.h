#pragma once
// The slick and the oiled shoreline as RFC 7946 GeoJSON, written through GDAL's GeoJSON driver
// (RFC7946=YES): coordinates reprojected from the reach's CRS to WGS 84 lon/lat through PROJ,
// exterior rings counter-clockwise, holes clockwise.
//
// slick.geojson: per output time, the polygons of the reach's cells the floating oil covers
// (8-connected) by the film's Bonn Agreement appearance class (appearance.h), each with its time,
// area, code, appearance and thickness range. shoreline.geojson: per output time, the bank bins
// that hold stranded oil as lines beside the centreline at the mean offset of their oil, each
// with its bank, km, class and volume.

#include <string>
#include <vector>

#include "farfield/model/banks.h"
#include "farfield/model/centreline.h"
#include "reach/grid.h"

namespace farfield {

struct SlickSnapshot {
  double t_s = 0;
  std::string clock;    // ISO 8601 UTC
  reach::Field oiled;   // m^2 covered per cell of the grid
  reach::Field volume;  // m^3 of emulsion per cell (its film is volume / oiled thick)
};

struct ShoreSnapshot {
  double t_s = 0;
  std::string clock;
  std::vector<double> held_m3;      // per bank bin
  std::vector<double> mean_offset;  // per bank bin: of its stranded oil from the centreline (m)
};

// Throw std::runtime_error naming the file when GDAL fails (a CRS PROJ cannot transform).
void write_slick_geojson(const std::string& path, const std::vector<SlickSnapshot>& snapshots,
                         const reach::Grid& grid, const std::string& crs_wkt);
// An ensemble's oiling of the banks: per bank bin, the share of members that stranded oil on
// it by `clock`, drawn at `mean_offset` (per bin, m).
struct ShoreProbability {
  double t_s = 0;
  std::string clock;
  std::vector<double> probability, mean_offset;  // per bank bin
  std::vector<int> kilometre;                    // each bin's group: a whole kilometre of a bank
  std::vector<double> kilometre_probability;     // per group
};

// With `probability`, shoreline.geojson also holds a line for each bank bin some member oiled,
// with its oiling probability (kind "probability"), and one for each whole kilometre of a bank
// some member oiled, with the share of members that oiled it anywhere (kind
// "probability_km"); the deterministic lines are kind "stranded".
void write_shoreline_geojson(const std::string& path, const std::vector<ShoreSnapshot>& snapshots,
                             const Centreline& centreline, const Banks& banks,
                             const std::string& crs_wkt,
                             const ShoreProbability* probability = nullptr);

}  // namespace farfield
