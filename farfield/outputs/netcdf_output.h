#pragma once
// The elements' trajectories as a CF-1.6 discrete-sampling-geometry NetCDF of featureType
// "trajectory", laid out as OpenDrift writes its own (so that its users' tools, e.g. trajan and
// opendrift.open, read it): dimensions (trajectory, time), one row per element with the fill
// value before it was released, variables lon, lat (degrees), status with flag_values and
// flag_meanings, and the oil's properties. Times are "seconds since" the forecast's start.

#include <string>
#include <vector>

namespace farfield {

// One output time: every variable has one value per element born so far.
struct ElementSnapshot {
  double t_s = 0;
  std::vector<float> lon, lat, x, y;
  std::vector<int> status;  // 0 floating, 1 stranded, 2 left the reach
  std::vector<float> mass_oil, mass_evaporated, mass_dispersed, water_fraction, thickness, density,
      viscosity, age;
};

struct NetcdfAttributes {
  std::string title, summary, start_iso, oil_name, oil_source, crs_wkt, history;
};

// Throws std::runtime_error naming the file and the NetCDF error.
void write_trajectory_netcdf(const std::string& path, const std::vector<ElementSnapshot>& snaps,
                             const NetcdfAttributes& attributes);

}  // namespace farfield
