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
  void text(int var, const char* name, const std::string& value) const {
    check(nc_put_att_text(id, var, name, value.size(), value.c_str()),
          std::string("write the attribute ") + name);
  }
  ~File() {
    if (id >= 0) nc_close(id);
  }
};

// The CF trajectory layout: one row per element (its id), one column per output time.
struct Layout {
  int trajectory_dim = -1, time_dim = -1;
  int trajectory_var = -1, time_var = -1;
};

Layout define_coordinates(const File& f, size_t elements, size_t times,
                          const std::string& start_iso) {
  Layout l;
  f.check(nc_def_dim(f.id, "trajectory", std::max<size_t>(elements, 1), &l.trajectory_dim),
          "define trajectory");
  f.check(nc_def_dim(f.id, "time", times, &l.time_dim), "define time");
  f.check(nc_def_var(f.id, "trajectory", NC_INT, 1, &l.trajectory_dim, &l.trajectory_var),
          "define trajectory");
  f.text(l.trajectory_var, "cf_role", "trajectory_id");
  f.text(l.trajectory_var, "units", "1");
  f.check(nc_def_var(f.id, "time", NC_DOUBLE, 1, &l.time_dim, &l.time_var), "define time");
  f.text(l.time_var, "standard_name", "time");
  f.text(l.time_var, "long_name", "time");
  f.text(l.time_var, "units", "seconds since " + start_iso);
  return l;
}

// One float variable per element and time, read from one member of the snapshots.
struct FloatVar {
  const char* name;
  const char* standard_name;
  const char* long_name;
  const char* units;
  std::vector<float> ElementSnapshot::*member;
  int id = -1;
};

std::vector<FloatVar> define_element_variables(const File& f, const Layout& l) {
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
  const int dims[2] = {l.trajectory_dim, l.time_dim};
  const float fill = std::numeric_limits<float>::quiet_NaN();
  for (FloatVar& v : vars) {
    f.check(nc_def_var(f.id, v.name, NC_FLOAT, 2, dims, &v.id), std::string("define ") + v.name);
    f.check(nc_def_var_fill(f.id, v.id, 0, &fill), std::string("set the fill of ") + v.name);
    if (*v.standard_name) f.text(v.id, "standard_name", v.standard_name);
    f.text(v.id, "long_name", v.long_name);
    f.text(v.id, "units", v.units);
    f.text(v.id, "coordinates", "lon lat time");
  }
  return vars;
}

int define_status(const File& f, const Layout& l) {
  const int dims[2] = {l.trajectory_dim, l.time_dim};
  int var;
  f.check(nc_def_var(f.id, "status", NC_INT, 2, dims, &var), "define status");
  const int status_fill = -2147483647;
  f.check(nc_def_var_fill(f.id, var, 0, &status_fill), "set the fill of status");
  const int flag_values[4] = {0, 1, 2, 3};
  f.check(nc_put_att_int(f.id, var, "flag_values", NC_INT, 4, flag_values), "flag_values");
  f.text(var, "flag_meanings", "active stranded left_reach sunk");
  f.text(var, "long_name",
         "status of the element: 0 floating, 1 stranded on a bank, 2 left the reach, 3 sunk "
         "to the bed");
  f.text(var, "coordinates", "lon lat time");
  return var;
}

void write_global_attributes(const File& f, const NetcdfAttributes& a) {
  f.text(NC_GLOBAL, "Conventions", "CF-1.6");
  f.text(NC_GLOBAL, "featureType", "trajectory");
  f.text(NC_GLOBAL, "title", a.title);
  f.text(NC_GLOBAL, "summary", a.summary);
  f.text(NC_GLOBAL, "source",
         "spill-sim forecast: Lagrangian oil elements on a reach's depth-averaged flow");
  f.text(NC_GLOBAL, "history", a.history);
  f.text(NC_GLOBAL, "time_coverage_start", a.start_iso);
  f.text(NC_GLOBAL, "oil_type", a.oil_name);
  f.text(NC_GLOBAL, "oil_source", a.oil_source);
  f.text(NC_GLOBAL, "crs_wkt", a.crs_wkt);
}

void write_values(const File& f, const std::vector<ElementSnapshot>& snaps, size_t elements,
                  const Layout& l, const std::vector<FloatVar>& vars, int status_var) {
  std::vector<int> ids(std::max<size_t>(elements, 1));
  for (size_t e = 0; e < ids.size(); ++e) ids[e] = int(e);
  f.check(nc_put_var_int(f.id, l.trajectory_var, ids.data()), "write trajectory");
  for (size_t k = 0; k < snaps.size(); ++k) {
    const size_t start[1] = {k}, count[1] = {1};
    f.check(nc_put_vara_double(f.id, l.time_var, start, count, &snaps[k].t_s), "write time");
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
}

}  // namespace

void write_trajectory_netcdf(const std::string& path, const std::vector<ElementSnapshot>& snaps,
                             const NetcdfAttributes& a) {
  File f{path};
  f.check(nc_create(path.c_str(), NC_CLOBBER | NC_NETCDF4, &f.id), "create the file");
  const size_t elements = snaps.empty() ? 0 : snaps.back().lon.size();
  const Layout layout = define_coordinates(f, elements, snaps.size(), a.start_iso);
  const std::vector<FloatVar> vars = define_element_variables(f, layout);
  const int status_var = define_status(f, layout);
  write_global_attributes(f, a);
  f.check(nc_enddef(f.id), "end the definitions");
  write_values(f, snaps, elements, layout, vars, status_var);
  f.check(nc_close(f.id), "close the file");
  f.id = -1;
}

}  // namespace farfield
