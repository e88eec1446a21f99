#include "farfield/outputs/netcdf_output.h"

#include <netcdf.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace farfield {

namespace {

struct File {
  std::string path;
  int id = -1;
  void check(int status, const std::string& what) const {
    if (status != NC_NOERR)
      throw std::runtime_error(path + ": NetCDF could not " + what + " (" + nc_strerror(status) +
                               ")");
  }
  ~File() {
    if (id >= 0) nc_close(id);
  }
};

}  // namespace

void write_trajectory_netcdf(const std::string& path, const std::vector<ElementSnapshot>& snaps,
                             const NetcdfAttributes& a) {
  File f{path};
  f.check(nc_create(path.c_str(), NC_CLOBBER | NC_NETCDF4, &f.id), "create the file");
  const size_t elements = snaps.empty() ? 0 : snaps.back().lon.size();
  int trajectory_dim, time_dim;
  f.check(nc_def_dim(f.id, "trajectory", std::max<size_t>(elements, 1), &trajectory_dim),
          "define trajectory");
  f.check(nc_def_dim(f.id, "time", snaps.size(), &time_dim), "define time");
  const auto text = [&](int var, const char* name, const std::string& value) {
    f.check(nc_put_att_text(f.id, var, name, value.size(), value.c_str()),
            std::string("write the attribute ") + name);
  };

  int trajectory_var, time_var;
  f.check(nc_def_var(f.id, "trajectory", NC_INT, 1, &trajectory_dim, &trajectory_var),
          "define trajectory");
  text(trajectory_var, "cf_role", "trajectory_id");
  text(trajectory_var, "units", "1");
  f.check(nc_def_var(f.id, "time", NC_DOUBLE, 1, &time_dim, &time_var), "define time");
  text(time_var, "standard_name", "time");
  text(time_var, "long_name", "time");
  text(time_var, "units", "seconds since " + a.start_iso);

  const int dims[2] = {trajectory_dim, time_dim};
  const float fill = std::numeric_limits<float>::quiet_NaN();
  struct FloatVar {
    const char* name;
    const char* standard_name;
    const char* long_name;
    const char* units;
    std::vector<float> ElementSnapshot::*member;
    int id = -1;
  };
  std::vector<FloatVar> vars = {
      {"lon", "longitude", "longitude", "degrees_east", &ElementSnapshot::lon},
      {"lat", "latitude", "latitude", "degrees_north", &ElementSnapshot::lat},
      {"x", "projection_x_coordinate", "easting in the reach's CRS", "m", &ElementSnapshot::x},
      {"y", "projection_y_coordinate", "northing in the reach's CRS", "m", &ElementSnapshot::y},
      {"mass_oil", "", "oil mass on the element", "kg", &ElementSnapshot::mass_oil},
      {"mass_evaporated", "", "oil mass evaporated from the element", "kg",
       &ElementSnapshot::mass_evaporated},
      {"mass_dispersed", "", "oil mass dispersed into the water column", "kg",
       &ElementSnapshot::mass_dispersed},
      {"water_fraction", "", "water fraction of the emulsion's volume", "1",
       &ElementSnapshot::water_fraction},
      {"oil_film_thickness", "", "thickness of the element's emulsion", "m",
       &ElementSnapshot::thickness},
      {"density", "", "emulsion density", "kg m-3", &ElementSnapshot::density},
      {"viscosity", "", "emulsion kinematic viscosity", "m2 s-1", &ElementSnapshot::viscosity},
      {"age_seconds", "", "time since release", "s", &ElementSnapshot::age},
  };
  for (FloatVar& v : vars) {
    f.check(nc_def_var(f.id, v.name, NC_FLOAT, 2, dims, &v.id), std::string("define ") + v.name);
    f.check(nc_def_var_fill(f.id, v.id, 0, &fill), std::string("set the fill of ") + v.name);
    if (*v.standard_name) text(v.id, "standard_name", v.standard_name);
    text(v.id, "long_name", v.long_name);
    text(v.id, "units", v.units);
    text(v.id, "coordinates", "lon lat time");
  }
  int status_var;
  f.check(nc_def_var(f.id, "status", NC_INT, 2, dims, &status_var), "define status");
  const int status_fill = -2147483647;
  f.check(nc_def_var_fill(f.id, status_var, 0, &status_fill), "set the fill of status");
  const int flag_values[3] = {0, 1, 2};
  f.check(nc_put_att_int(f.id, status_var, "flag_values", NC_INT, 3, flag_values), "flag_values");
  text(status_var, "flag_meanings", "active stranded left_reach");
  text(status_var, "long_name",
       "status of the element: 0 floating, 1 stranded on a bank, 2 left the reach");
  text(status_var, "coordinates", "lon lat time");

  text(NC_GLOBAL, "Conventions", "CF-1.6");
  text(NC_GLOBAL, "featureType", "trajectory");
  text(NC_GLOBAL, "title", a.title);
  text(NC_GLOBAL, "summary", a.summary);
  text(NC_GLOBAL, "source",
       "spill-sim forecast: Lagrangian oil elements on a reach's depth-averaged flow");
  text(NC_GLOBAL, "history", a.history);
  text(NC_GLOBAL, "time_coverage_start", a.start_iso);
  text(NC_GLOBAL, "oil_type", a.oil_name);
  text(NC_GLOBAL, "oil_source", a.oil_source);
  text(NC_GLOBAL, "crs_wkt", a.crs_wkt);
  f.check(nc_enddef(f.id), "end the definitions");

  std::vector<int> ids(std::max<size_t>(elements, 1));
  for (size_t e = 0; e < ids.size(); ++e) ids[e] = int(e);
  f.check(nc_put_var_int(f.id, trajectory_var, ids.data()), "write trajectory");
  for (size_t k = 0; k < snaps.size(); ++k) {
    const size_t start[1] = {k}, count[1] = {1};
    f.check(nc_put_vara_double(f.id, time_var, start, count, &snaps[k].t_s), "write time");
  }
  // Column by column (one time at a time), the elements not born yet left at the fill value.
  for (size_t k = 0; k < snaps.size(); ++k) {
    const size_t n = snaps[k].lon.size();
    if (n == 0) continue;
    const size_t start[2] = {0, k}, count[2] = {n, 1};
    for (const FloatVar& v : vars)
      f.check(nc_put_vara_float(f.id, v.id, start, count, (snaps[k].*v.member).data()),
              std::string("write ") + v.name);
    f.check(nc_put_vara_int(f.id, status_var, start, count, snaps[k].status.data()),
            "write status");
  }
  f.check(nc_close(f.id), "close the file");
  f.id = -1;
}

}  // namespace farfield
