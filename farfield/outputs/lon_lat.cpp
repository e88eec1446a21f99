#include "farfield/outputs/lon_lat.h"

#include <ogr_spatialref.h>

#include <stdexcept>

namespace farfield {

LonLat::LonLat(const std::string& crs_wkt) {
  OGRSpatialReference source, wgs84;
  if (crs_wkt.empty() || source.importFromWkt(crs_wkt.c_str()) != OGRERR_NONE)
    throw std::runtime_error("the reach's CRS is missing or not WKT GDAL reads");
  wgs84.importFromEPSG(4326);
  source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  transform_.reset(OGRCreateCoordinateTransformation(&source, &wgs84));
  if (!transform_) throw std::runtime_error("PROJ cannot transform the reach's CRS to WGS 84");
}

LonLat::~LonLat() = default;

void LonLat::convert(double x, double y, double& lon, double& lat) const {
  lon = x;
  lat = y;
  if (!transform_->Transform(1, &lon, &lat))
    throw std::runtime_error("PROJ could not transform a point to WGS 84");
}

}  // namespace farfield
